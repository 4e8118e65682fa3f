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
// If write throws or leaves no file, tmp is removed and the error propagates.
void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path& tmp)>& write);

void write_file_atomically(const std::filesystem::path& target, std::string_view bytes);

}  // namespace gslift
