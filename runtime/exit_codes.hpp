// Process exit codes of the gslift command line (also listed by `gslift --help` and the README).
// Schedulers key retry policies on them: an invalid graph never succeeds on retry, an
// interruption usually does.
#pragma once

namespace gslift::exit_code {

constexpr int kOk = 0;
constexpr int kRunsDiffer = 1;    // diff: the two runs differ (as diff(1))
constexpr int kUsage = 2;         // bad command line
constexpr int kInvalidGraph = 3;  // the YAML graph failed validation
constexpr int kBadInput = 4;      // an input file is missing or unreadable (InputError)
constexpr int kNodeFailed = 5;    // a node threw while running
constexpr int kBatchPartial = 6;  // batch: some captures failed, the others are done
constexpr int kInternal = 70;     // a bug: an unexpected exception escaped the runtime
constexpr int kCannotWrite = 73;  // results cannot be written (disk full, read-only, no permission)
constexpr int kInterrupted = 130;  // SIGINT/SIGTERM: stopped cleanly, partial outputs removed

}  // namespace gslift::exit_code
