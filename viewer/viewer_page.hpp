// The viewer's page (viewer/page/viewer.html: HTML, CSS and script in one file, nothing fetched
// from elsewhere), embedded into the binary at build time.
#pragma once

namespace gslift {

extern const char* const kViewerPage;

}  // namespace gslift
