#include "app/report_html.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"

#ifndef CAVESIM_MODEL_VIEWER_DIR
#define CAVESIM_MODEL_VIEWER_DIR ""
#endif

namespace fs = std::filesystem;

namespace cavesim::app {
namespace {

std::string escape(const std::string& s) {
    std::string out;
    out.reserve(s.size());
    for (char c : s) {
        switch (c) {
            case '&':
                out += "&amp;";
                break;
            case '<':
                out += "&lt;";
                break;
            case '>':
                out += "&gt;";
                break;
            case '"':
                out += "&quot;";
                break;
            default:
                out += c;
        }
    }
    return out;
}

/// Inline Markdown: `code` (verbatim, escaped) and **bold**; everything else escaped.
std::string inlineHtml(const std::string& s) {
    std::string out;
    bool bold = false;
    for (std::size_t i = 0; i < s.size();) {
        if (s[i] == '`') {
            const std::size_t end = s.find('`', i + 1);
            if (end != std::string::npos) {
                out += "<code>" + escape(s.substr(i + 1, end - i - 1)) + "</code>";
                i = end + 1;
                continue;
            }
        }
        if (s.compare(i, 2, "**") == 0) {
            out += bold ? "</strong>" : "<strong>";
            bold = !bold;
            i += 2;
            continue;
        }
        out += escape(std::string(1, s[i]));
        ++i;
    }
    if (bold) out += "</strong>";
    return out;
}

std::vector<std::string> cells(const std::string& row) {
    std::vector<std::string> out;
    std::string t = row;
    if (!t.empty() && t.front() == '|') t.erase(0, 1);
    if (!t.empty() && t.back() == '|') t.pop_back();
    std::stringstream ss(t);
    std::string cell;
    while (std::getline(ss, cell, '|')) {
        const std::size_t a = cell.find_first_not_of(' '), b = cell.find_last_not_of(' ');
        out.push_back(a == std::string::npos ? std::string() : cell.substr(a, b - a + 1));
    }
    return out;
}

std::string base64(const std::string& bytes) {
    static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    std::size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        const unsigned v = unsigned(static_cast<unsigned char>(bytes[i])) << 16 |
                           unsigned(static_cast<unsigned char>(bytes[i + 1])) << 8 |
                           unsigned(static_cast<unsigned char>(bytes[i + 2]));
        out += k[v >> 18], out += k[(v >> 12) & 63], out += k[(v >> 6) & 63], out += k[v & 63];
    }
    if (i < bytes.size()) {
        unsigned v = unsigned(static_cast<unsigned char>(bytes[i])) << 16;
        if (i + 1 < bytes.size()) v |= unsigned(static_cast<unsigned char>(bytes[i + 1])) << 8;
        out += k[v >> 18], out += k[(v >> 12) & 63];
        out += i + 1 < bytes.size() ? k[(v >> 6) & 63] : '=';
        out += '=';
    }
    return out;
}

const char* kStyle = R"(body{font-family:"DejaVu Sans",system-ui,sans-serif;color:#19191e;background:#fafafa;margin:0}
main{max-width:1100px;margin:0 auto;padding:1.5em 2em 4em}
h1{font-size:1.7em;margin-bottom:.3em}h2{margin-top:1.8em;border-bottom:1px solid #ddd;padding-bottom:.2em}
table{border-collapse:collapse;margin:1em 0;font-size:.92em}th,td{border:1px solid #d5d5d5;padding:.3em .6em;text-align:left}
th{background:#eee}code{font-family:"DejaVu Sans Mono",monospace;font-size:.92em;background:#f0f0f0;padding:0 .2em}
figure{margin:1.2em 0}figure img{max-width:100%;border:1px solid #e0e0e0;background:#fff}
figcaption{color:#555;font-size:.9em}
#view3d model-viewer{display:block;width:100%;height:560px;background:#1d2230;border-radius:4px}
.note{color:#555;font-size:.9em}.missing{background:#fff4e0;border:1px solid #e8c88a;padding:.8em 1em;border-radius:4px}
details summary{cursor:pointer;color:#333})";

}  // namespace

std::string modelViewerDir() {
    if (const char* env = std::getenv("CAVESIM_MODEL_VIEWER_DIR")) return env;
    return CAVESIM_MODEL_VIEWER_DIR;
}

std::string markdownToHtml(const std::string& md) {
    std::vector<std::string> lines;
    {
        std::stringstream ss(md);
        std::string line;
        while (std::getline(ss, line)) lines.push_back(line);
    }
    std::ostringstream html;
    std::string paragraph;
    auto flush = [&] {
        if (!paragraph.empty()) html << "<p>" << inlineHtml(paragraph) << "</p>\n";
        paragraph.clear();
    };
    bool inDetails = false;
    for (std::size_t i = 0; i < lines.size(); ++i) {
        const std::string& l = lines[i];
        if (l.empty()) {
            flush();
            continue;
        }
        if (l.rfind("# ", 0) == 0 || l.rfind("## ", 0) == 0) {
            flush();
            if (inDetails) html << "</details>\n", inDetails = false;
            const bool h1 = l[1] == ' ';
            const std::string title = l.substr(h1 ? 2 : 3);
            html << (h1 ? "<h1>" : "<h2>") << inlineHtml(title) << (h1 ? "</h1>\n" : "</h2>\n");
            if (title == "Parameters") {  // long: folded
                html << "<details><summary>every key of the scenario</summary>\n";
                inDetails = true;
            }
            continue;
        }
        if (l.front() == '|') {
            flush();
            html << "<table>\n";
            bool header = true;
            for (; i < lines.size() && !lines[i].empty() && lines[i].front() == '|'; ++i) {
                const std::vector<std::string> c = cells(lines[i]);
                if (!c.empty() && c[0].find_first_not_of("-:") == std::string::npos) continue;  // |---|
                html << "<tr>";
                for (const std::string& x : c)
                    html << (header ? "<th>" : "<td>") << inlineHtml(x) << (header ? "</th>" : "</td>");
                html << "</tr>\n";
                header = false;
            }
            --i;
            html << "</table>\n";
            continue;
        }
        if (l.rfind("- ", 0) == 0) {
            flush();
            html << "<ul>\n";
            for (; i < lines.size() && lines[i].rfind("- ", 0) == 0; ++i)
                html << "<li>" << inlineHtml(lines[i].substr(2)) << "</li>\n";
            --i;
            html << "</ul>\n";
            continue;
        }
        const std::size_t mid = l.find("](");
        if (l.rfind("![", 0) == 0 && mid != std::string::npos && l.back() == ')') {
            flush();
            const std::string alt = l.substr(2, mid - 2), src = l.substr(mid + 2, l.size() - mid - 3);
            html << "<figure><img src=\"" << escape(src) << "\" alt=\"" << escape(alt) << "\"><figcaption>"
                 << inlineHtml(alt) << "</figcaption></figure>\n";
            continue;
        }
        paragraph += (paragraph.empty() ? "" : " ") + l;
    }
    flush();
    if (inDetails) html << "</details>\n";
    return html.str();
}

std::string reportHtml(const std::string& markdown, const std::string& glb, const std::string& viewerScript) {
    // The title and the first paragraph above the 3D view, the rest below it.
    std::string head = markdown, rest;
    const std::size_t cut = markdown.find("\n## ");
    if (cut != std::string::npos) head = markdown.substr(0, cut + 1), rest = markdown.substr(cut + 1);
    std::string title = "cavesim report";
    if (markdown.rfind("# ", 0) == 0) title = markdown.substr(2, markdown.find('\n') - 2);

    std::ostringstream h;
    h << "<!doctype html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
      << "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
      << "<title>" << escape(title) << "</title>\n<style>\n"
      << kStyle << "\n</style>\n";
    const bool view = !glb.empty() && !viewerScript.empty();
    if (view) h << "<script src=\"" << escape(viewerScript) << "\"></script>\n";
    h << "</head>\n<body>\n<main>\n" << markdownToHtml(head);
    h << "<section id=\"view3d\">\n<h2>Interactive 3D view</h2>\n";
    if (view) {
        h << "<model-viewer id=\"cave\" alt=\"The cave mesh (cave.glb)\" camera-controls touch-action=\"pan-y\" "
             "interaction-prompt=\"none\" camera-orbit=\"-25deg 50deg auto\" shadow-intensity=\"0.6\" exposure=\"1.1\" "
             "src=\"data:model/gltf-binary;base64,"
          << base64(glb) << "\"></model-viewer>\n";
        h << "<p class=\"note\">cave.glb (metres, glTF y up), embedded in this page. Drag to turn, scroll or pinch "
             "to zoom, right-drag to pan. Viewer: Google's &lt;model-viewer&gt; (Apache-2.0; three.js, MIT; lit, "
             "BSD-3-Clause), in <code>report_files/</code>.</p>\n";
    } else {
        h << "<p class=\"missing\">No interactive 3D view: ";
        if (glb.empty())
            h << "this run wrote no <code>cave.glb</code> (the <code>glb</code> format is not in "
                 "<code>--formats</code> / <code>[output] formats</code>, or <code>[output] mesh = false</code>).";
        else
            h << "the viewer script (<code>" << kModelViewerScript
              << "</code>, Google's &lt;model-viewer&gt;) was not found when this page was written. "
                 "<code>bash scripts/setup.sh</code> fetches it; then <code>cavesim report DIR</code> rewrites the "
                 "page with the 3D view. The pictures below show the cave.";
        h << "</p>\n";
    }
    h << "</section>\n" << markdownToHtml(rest) << "</main>\n</body>\n</html>\n";
    return h.str();
}

void writeReportHtml(const std::string& dir, const std::string& markdown, const std::string& viewerDir) {
    const fs::path out(dir);
    std::string glb;
    if (fs::exists(out / "cave.glb")) glb = readFileBytes(out / "cave.glb");
    std::string script;
    const fs::path viewer = fs::path(viewerDir) / kModelViewerScript;
    if (!glb.empty() && !viewerDir.empty() && fs::is_regular_file(viewer)) {
        std::error_code ec;
        fs::create_directories(out / "report_files", ec);
        if (ec) throw RuntimeError("cannot create " + (out / "report_files").string() + ": " + ec.message());
        writeFileAtomic((out / "report_files" / kModelViewerScript).string(), readFileBytes(viewer));
        const fs::path licence = fs::path(viewerDir) / "LICENSE";
        if (fs::is_regular_file(licence))
            writeFileAtomic((out / "report_files" / "model-viewer-LICENSE").string(), readFileBytes(licence));
        script = std::string("report_files/") + kModelViewerScript;
    }
    writeFileAtomic((out / "report.html").string(), reportHtml(markdown, glb, script));
}

}  // namespace cavesim::app
