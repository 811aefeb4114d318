#include "render/colormap.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace cavesim::render {
namespace {

template <std::size_t N>
Rgb ramp(const std::array<Rgb, N>& stops, double t) {
    if (!std::isfinite(t)) t = 0.0;
    t = std::clamp(t, 0.0, 1.0) * double(N - 1);
    const std::size_t i = std::min<std::size_t>(std::size_t(t), N - 2);
    return mix(stops[i], stops[i + 1], t - double(i));
}

}  // namespace

Rgb viridis(double t) {
    // Samples of the viridis map at 0, 1/8, ..., 1.
    static const std::array<Rgb, 9> stops{{{68, 1, 84},
                                           {71, 44, 122},
                                           {59, 81, 139},
                                           {44, 113, 142},
                                           {33, 144, 141},
                                           {39, 173, 129},
                                           {92, 200, 99},
                                           {170, 220, 50},
                                           {253, 231, 37}}};
    return ramp(stops, t);
}

Rgb inferno(double t) {
    static const std::array<Rgb, 9> stops{{{0, 0, 4},
                                           {31, 12, 72},
                                           {85, 15, 109},
                                           {136, 34, 106},
                                           {186, 54, 85},
                                           {227, 89, 51},
                                           {249, 140, 10},
                                           {249, 201, 50},
                                           {252, 255, 164}}};
    return ramp(stops, t);
}

Rgb depthRamp(double t) {
    static const std::array<Rgb, 5> stops{{{236, 196, 120}, {214, 150, 96}, {170, 118, 120}, {110, 110, 150}, {70, 90, 140}}};
    return ramp(stops, t);
}

Rgb zoneColour(int id) {
    if (id < 0) return {230, 230, 230};
    // A qualitative palette (Tableau-like), distinct on screen and in print.
    static const std::array<Rgb, 12> palette{{{78, 121, 167},
                                              {242, 142, 43},
                                              {89, 161, 79},
                                              {237, 201, 72},
                                              {176, 122, 161},
                                              {118, 183, 178},
                                              {255, 157, 167},
                                              {156, 117, 95},
                                              {186, 176, 172},
                                              {225, 87, 89},
                                              {134, 188, 242},
                                              {160, 203, 100}}};
    return palette[std::size_t(id) % palette.size()];
}

}  // namespace cavesim::render
