// report.html: the Markdown subset of report.md, the embedded model, the page without a viewer;
// the section measures of a 2D section.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "app/report_html.h"
#include "app/report_section.h"

namespace cavesim::app {
namespace {

TEST(ReportHtml, MarkdownSubset) {
    const std::string html = markdownToHtml(
        "# Title\n\nA `key` and **bold** <text>.\n\n## Part\n\n| a | b |\n|---|---|\n| `x` | 1 |\n\n- one\n- two\n\n"
        "![the plan](images/plan.png)\n");
    EXPECT_NE(html.find("<h1>Title</h1>"), std::string::npos);
    EXPECT_NE(html.find("<p>A <code>key</code> and <strong>bold</strong> &lt;text&gt;.</p>"), std::string::npos);
    EXPECT_NE(html.find("<h2>Part</h2>"), std::string::npos);
    EXPECT_NE(html.find("<tr><th>a</th><th>b</th></tr>\n<tr><td><code>x</code></td><td>1</td></tr>"),
              std::string::npos);
    EXPECT_EQ(html.find("---"), std::string::npos);
    EXPECT_NE(html.find("<ul>\n<li>one</li>\n<li>two</li>\n</ul>"), std::string::npos);
    EXPECT_NE(html.find("<figure><img src=\"images/plan.png\" alt=\"the plan\">"), std::string::npos);
}

TEST(ReportHtml, EmbedsTheModelAsBase64WhenTheViewerIsThere) {
    const std::string md = "# r\n\nintro\n\n## Timings\n\nt\n";
    const std::string page = reportHtml(md, "glTFab", "report_files/v.js");
    EXPECT_NE(page.find("<script src=\"report_files/v.js\"></script>"), std::string::npos);
    EXPECT_NE(page.find("src=\"data:model/gltf-binary;base64,Z2xURmFi\""), std::string::npos);  // "glTFab"
    // The 3D view sits between the introduction and the first section.
    EXPECT_LT(page.find("intro"), page.find("<model-viewer"));
    EXPECT_LT(page.find("<model-viewer"), page.find("<h2>Timings</h2>"));
    EXPECT_NE(reportHtml(md, "glTFa", "v.js").find("base64,Z2xURmE=\""), std::string::npos);
}

TEST(ReportHtml, SaysWhyThereIsNoView) {
    const std::string noViewer = reportHtml("# r\n", "glTF", "");
    EXPECT_EQ(noViewer.find("<script"), std::string::npos);
    EXPECT_EQ(noViewer.find("<model-viewer"), std::string::npos);
    EXPECT_NE(noViewer.find("viewer script"), std::string::npos);
    EXPECT_NE(reportHtml("# r\n", "", "v.js").find("no <code>cave.glb</code>"), std::string::npos);
}

TEST(ReportHtml, WritesThePageAndCopiesTheViewer) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / "cavesim_test_report_html";
    fs::remove_all(dir);
    fs::create_directories(dir / "viewer");
    std::ofstream(dir / "viewer" / kModelViewerScript) << "/* viewer */";
    std::ofstream(dir / "viewer" / "LICENSE") << "Apache";
    std::ofstream(dir / "cave.glb") << "glTF";
    writeReportHtml(dir.string(), "# r\n", (dir / "viewer").string());
    EXPECT_TRUE(fs::exists(dir / "report_files" / kModelViewerScript));
    EXPECT_TRUE(fs::exists(dir / "report_files" / "model-viewer-LICENSE"));
    EXPECT_TRUE(fs::exists(dir / "report.html"));
    fs::remove_all(dir);
}

TEST(ReportSection, MeasuresInTheSectionPlane) {
    Scenario s;
    s.size = {80, 1, 40};
    s.voxelSize = 0.5;
    EXPECT_TRUE(isSectionScenario(s));
    const nlohmann::json r = {{"morphometry", {{"length_m", 50.0}, {"volume_m3", 25.0}, {"vertical_range_m", 10.0}}}};
    const std::string md = sectionMeasuresMarkdown(s, r);
    EXPECT_NE(md.find("| cave area in the section (m²) | 50 |"), std::string::npos);  // 25 m³ / 0.5 m
    EXPECT_NE(md.find("| section area (m²) | 800 |"), std::string::npos);
    EXPECT_NE(md.find("| cave share of the section (%) | 6.25 |"), std::string::npos);
    EXPECT_NE(md.find("area / length (m) | 1 |"), std::string::npos);
    s.size = {80, 2, 40};
    EXPECT_FALSE(isSectionScenario(s));
}

}  // namespace
}  // namespace cavesim::app
