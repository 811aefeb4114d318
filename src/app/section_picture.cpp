#include "app/section_picture.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "render/colormap.h"
#include "render/png_io.h"

namespace cavesim::app {

namespace {

constexpr int kPanel = 220;   // panel width and slice area height, pixels
constexpr int kCaption = 40;  // caption height under a panel
constexpr int kHeader = 24;   // column header height
constexpr int kTitle = 30;    // picture title height

render::Rgb classColour(morpho::SectionClass c) {
    switch (c) {
        case morpho::SectionClass::kTube:
            return {40, 110, 200};
        case morpho::SectionClass::kCanyon:
            return {200, 90, 40};
        case morpho::SectionClass::kKeyhole:
            return {120, 60, 170};
        case morpho::SectionClass::kOther:
        case morpho::SectionClass::kShort:
            break;
    }
    return {90, 90, 90};
}

std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2g", v);
    if (std::fabs(v) >= 10) std::snprintf(buf, sizeof buf, "%.0f", v);
    return buf;
}

void drawPanel(render::Image& img, int x0, int y0, const morpho::PassageSection& p) {
    const morpho::SectionSlice& s = p.example;
    int c0 = s.cols, c1 = -1, r0 = s.rows, r1 = -1;
    for (int r = 0; r < s.rows; ++r)
        for (int c = 0; c < s.cols; ++c)
            if (s.cells[std::size_t(r) * std::size_t(s.cols) + std::size_t(c)]) {
                c0 = std::min(c0, c);
                c1 = std::max(c1, c);
                r0 = std::min(r0, r);
                r1 = std::max(r1, r);
            }
    if (c1 < 0) return;
    // One sample of rock around the section.
    c0 = std::max(c0 - 1, 0);
    r0 = std::max(r0 - 1, 0);
    c1 = std::min(c1 + 1, s.cols - 1);
    r1 = std::min(r1 + 1, s.rows - 1);
    const int cols = c1 - c0 + 1, rows = r1 - r0 + 1;
    const int area = kPanel - 20;
    const int px = std::max(1, std::min(area / cols, area / rows));
    const int ox = x0 + (kPanel - cols * px) / 2, oy = y0 + 10 + (area - rows * px) / 2;
    fillRect(img, ox, oy, cols * px, rows * px, render::colours::kRock);
    const render::Rgb colour = classColour(p.cls);
    for (int r = r0; r <= r1; ++r)
        for (int c = c0; c <= c1; ++c)
            if (s.cells[std::size_t(r) * std::size_t(s.cols) + std::size_t(c)])
                fillRect(img, ox + (c - c0) * px, oy + (r - r0) * px, px, px, colour);
    // Scale bar: the longest of 0.5, 1, 2, 5, 10, 20, 50 m within 40% of the panel.
    const double pxPerMetre = px / s.step;
    double bar = 0.5;
    for (double b : {1.0, 2.0, 5.0, 10.0, 20.0, 50.0})
        if (b * pxPerMetre <= 0.4 * kPanel) bar = b;
    const int barPx = int(std::lround(bar * pxPerMetre));
    const int by = y0 + kPanel - 6;
    fillRect(img, x0 + 8, by, barPx, 3, render::colours::kText);
    render::drawText(img, x0 + 12 + barPx, by - 6, number(bar) + " m", render::colours::kText, 1);
    const std::string line1 = "p" + std::to_string(p.passage) + "  z " + number(p.z_m) + " m";
    const std::string line2 = "w " + number(p.exampleShape.width_m) + " m  h " + number(p.exampleShape.height_m) + " m";
    render::drawTextAligned(img, x0 + kPanel / 2, y0 + kPanel + 4, line1, render::colours::kText, 1,
                            render::Align::kCentre);
    render::drawTextAligned(img, x0 + kPanel / 2, y0 + kPanel + 20, line2, render::colours::kText, 1,
                            render::Align::kCentre);
}

}  // namespace

render::Image sectionsPicture(const morpho::CrossSections& sections, const std::string& title) {
    std::vector<std::vector<const morpho::PassageSection*>> columns;
    std::vector<morpho::SectionClass> classes;
    for (int k = 0; k < morpho::kSectionClasses; ++k) {
        std::vector<const morpho::PassageSection*> of;
        for (const morpho::PassageSection& p : sections.passages)
            if (int(p.cls) == k && !p.example.cells.empty()) of.push_back(&p);
        if (of.empty()) continue;
        std::stable_sort(of.begin(), of.end(), [](const morpho::PassageSection* a, const morpho::PassageSection* b) {
            return a->length_m > b->length_m;
        });
        if (int(of.size()) > kSectionExamplesPerClass) of.resize(std::size_t(kSectionExamplesPerClass));
        columns.push_back(of);
        classes.push_back(morpho::SectionClass(k));
    }
    if (columns.empty()) return {};
    int maxRows = 0;
    for (const auto& c : columns) maxRows = std::max(maxRows, int(c.size()));
    const int width = std::max(int(columns.size()) * kPanel, 2 * kPanel);
    const int height = kTitle + kHeader + maxRows * (kPanel + kCaption);
    render::Image img(width, height, render::colours::kWhite);
    render::drawText(img, 8, 8, "Passage cross-sections, looking along each passage: " + title, render::colours::kText,
                     1);
    for (std::size_t c = 0; c < columns.size(); ++c) {
        const int x0 = int(c) * kPanel;
        long n = 0;
        for (const morpho::PassageSection& p : sections.passages) n += p.cls == classes[c] ? 1 : 0;
        render::drawTextAligned(img, x0 + kPanel / 2, kTitle,
                                std::string(morpho::sectionClassName(classes[c])) + " (" + std::to_string(n) +
                                    " passage" + (n == 1 ? "" : "s") + ")",
                                classColour(classes[c]), 1, render::Align::kCentre);
        for (std::size_t r = 0; r < columns[c].size(); ++r)
            drawPanel(img, x0, kTitle + kHeader + int(r) * (kPanel + kCaption), *columns[c][r]);
        if (c > 0) render::drawLine(img, x0 + 0.5, kTitle, x0 + 0.5, height, render::colours::kLightGrey);
    }
    return img;
}

std::string writeSectionsPicture(const morpho::CrossSections& sections, const std::string& title,
                                 const std::string& imagesDir) {
    const render::Image img = sectionsPicture(sections, title);
    if (img.width == 0) return {};
    render::writePng((std::filesystem::path(imagesDir) / "sections.png").string(), img);
    return "sections.png";
}

}  // namespace cavesim::app
