// The folder a command writes its results into (--out): checked before anything runs, and named
// with what it holds in the closing line.
#pragma once

#include <filesystem>
#include <string>

namespace gslift {

// An output folder that exists as something else (a file, a device) is bad input named by its
// path, before anything runs (it used to end as an internal error when run.json was written).
// The folder is created, and its writability tried, here: a read-only or unwritable folder is one
// clear error (OutputError), not a run that fails at its first output.
void check_output_folder(const std::filesystem::path& out);

// `gslift run --out`: gslift writes run.json and node folders into it and removes its own stale
// temporaries there, so it must be a results folder: new, empty, or holding a run.json (an
// earlier run's). Anything else (`--out /`, a home folder, a typo naming a project) is refused
// before a file is written. A folder holding only gslift.log is one a sweep or batch made for
// this run (the child's log is opened before it starts).
void check_results_folder(const std::filesystem::path& out);

// "out/demo (run.json, capture/, ...)"
std::string results_line(const std::filesystem::path& out);

}  // namespace gslift
