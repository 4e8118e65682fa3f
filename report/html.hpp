// The pieces every report page is made of: escaped text, files embedded as data URIs (so the page
// needs nothing beside it), and the page shell with its style sheet. No scripts, no external URLs.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace gslift::report {

// Text for HTML content and attribute values (& < > " ' escaped).
std::string html_escape(const std::string& text);

// A link to a file beside the page: "./" and the relative path with every byte but
// [A-Za-z0-9-._~/] percent-encoded, so that no folder name (`javascript:alert(1)`, `//host`, one
// with '#' or '?') can make it a link to a script, another site or another part of the page.
std::string relative_href(const std::filesystem::path& relative);

// RFC 4648 base64 with padding.
std::string base64(const std::string& bytes);

// The whole file; throws InputError naming it when it cannot be read.
std::string read_bytes(const std::filesystem::path& file);

// A picture's pixel size read from its header (PNG IHDR, JPEG SOFn); 0 x 0 when the header is not
// one of these.
struct PixelSize {
  uint32_t width = 0, height = 0;
};
PixelSize picture_size(const std::string& bytes);

// "image/png" or "image/jpeg" by the file's extension (case-insensitive); empty for others.
std::string picture_mime(const std::filesystem::path& file);

// A Markdown pipe table (the header row, the |---| row, the body rows; as eval/metrics.md holds
// it) as an HTML table, cells escaped, columns aligned right where the |---:| row says so. Lines
// that are not table rows are left out; empty when there is no table.
std::string markdown_table_html(const std::string& markdown);

// "12.3 KB", "4.5 MB".
std::string size_text(uintmax_t bytes);

// The Content-Security-Policy of every page: its own style and pictures (embedded or beside it)
// and nothing else: no script, no frames, no forms, no other base URL.
extern const char* const kContentSecurityPolicy;

// A complete page: <!DOCTYPE html>, kContentSecurityPolicy, the style sheet, `title` and `body`.
std::string html_page(const std::string& title, const std::string& body);

}  // namespace gslift::report
