// Every file gslift writes goes through these: write to a temporary name in the same folder, then
// rename() over the target, so a crash or interruption never leaves a half-written file that a
// rerun would take for a finished one.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

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

// The longest file name ext4, XFS, Btrfs and tmpfs take (NAME_MAX), in bytes.
constexpr size_t kMaxNameBytes = 255;

// `name`, shortened when `name` plus `extra_bytes` more would not fit kMaxNameBytes: then its
// first bytes (never half a UTF-8 character), '~' and 16 hex digits of the whole name's hash, so
// two long names that differ only at their ends stay apart. A name derived from a legal one
// (a temporary, a `.partial` folder) needs this: it is longer than what it derives from.
std::string fitting_name(const std::string& name, size_t extra_bytes);

// Whether a file name is one of write_atomically's temporaries, <stem>.gslift.tmp-<pid>-<n><ext>,
// and the process id it names (0 when it is not one).
int atomic_temporary_pid(const std::filesystem::path& name);

// Removes the temporaries a killed gslift process (SIGKILL, power loss) left in `out` and, at any
// depth, in out/<f> for each f in `folders` (the folders a run writes: its nodes' ids), and
// returns how many. Removes only regular files named as write_atomically names them whose process
// is gone, never a symlink's target or a folder gslift does not write, so another live run into
// the same folder and the user's own files are left alone.
size_t remove_stale_temporaries(const std::filesystem::path& out,
                                const std::vector<std::string>& folders);

}  // namespace gslift
