// Every file gslift writes goes through these: write to a temporary name in the same folder, then
// rename() over the target, so a crash or interruption never leaves a half-written file that a
// rerun would take for a finished one.
#pragma once

#include <filesystem>
#include <functional>
#include <string_view>

namespace gslift {

// Calls write(tmp) with a temporary path in target's folder that keeps target's extension (so
// cv::imwrite picks the right encoder), then renames tmp to target. Creates parent folders.
// If write throws or leaves no file, tmp is removed and the error propagates (a folder that cannot
// be created or a rename that fails: OutputError naming the path).
void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path& tmp)>& write);

// Throws OutputError naming target and the system's reason (e.g. "No space left on device") when
// the bytes cannot all be written; the temporary is removed.
void write_file_atomically(const std::filesystem::path& target, std::string_view bytes);

// Whether a file name is one of write_atomically's temporaries: <stem>.tmp-<pid>-<n><ext>.
bool is_atomic_temporary(const std::filesystem::path& name);

// Removes the temporaries a killed process (SIGKILL, power loss) left under dir, recursively, and
// returns how many. Only for a folder no other process is writing (gslift run's --out).
size_t remove_stale_temporaries(const std::filesystem::path& dir);

}  // namespace gslift
