/// @file report_html.h
/// @brief report.html: the report (report.md's content) as one web page with an interactive 3D
/// view of cave.glb, usable offline from `file://`.
///
/// The 3D view is Google's `<model-viewer>` (npm `@google/model-viewer`, Apache-2.0; its bundle
/// carries three.js, MIT, and lit, BSD-3-Clause), fetched once by scripts/setup.sh into
/// `<build>/vendor/model-viewer/`. The run copies its UMD bundle and licence into
/// `report_files/` beside the page: a classic script, because Chromium refuses ES-module scripts
/// from `file://`. cave.glb is embedded in the page as a `data:` URI, because the viewer fetches
/// its model and `file://` fetches are blocked. Without the viewer script, or without cave.glb,
/// the page is written without the 3D view and says why. The pictures are linked (images/…).
#pragma once

#include <string>

namespace cavesim::app {

/// Where the viewer is looked for: the directory in the environment variable
/// CAVESIM_MODEL_VIEWER_DIR when set, else the build's vendor directory (set at compile time).
std::string modelViewerDir();

/// The file name of the viewer script inside modelViewerDir() and report_files/.
inline constexpr const char* kModelViewerScript = "model-viewer-umd.min.js";

/// Converts the Markdown subset report.md uses (headings, paragraphs, `-` lists, pipe tables,
/// image lines, `code` and **bold**) to HTML body content; text is escaped.
std::string markdownToHtml(const std::string& markdown);

/// The whole page from report.md's text: `glb` (the bytes of cave.glb, empty when there is none)
/// is embedded when `viewerScript` (relative URL of the viewer script, empty when there is none)
/// is given; otherwise the page says which is missing.
std::string reportHtml(const std::string& markdown, const std::string& glb, const std::string& viewerScript);

/// Writes dir/report.html from `markdown` (report.md's text) and dir/cave.glb when present, and
/// copies the viewer (script and licence) from `viewerDir` into dir/report_files/ when it is
/// there; each file through a temporary name and a rename.
/// @throw RuntimeError when a file cannot be read or written
void writeReportHtml(const std::string& dir, const std::string& markdown,
                     const std::string& viewerDir = modelViewerDir());

}  // namespace cavesim::app
