// libFuzzer target: any bytes as state.cavesim. The reader must refuse what it did not write with
// InputError and never read out of bounds or allocate beyond the grid it accepts. The trailing
// file checksum is fixed up first (as a forger would), so the inputs reach the structure checks.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include "app/state_file.h"
#include "core/error.h"
#include "core/fnv.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::string bytes(reinterpret_cast<const char*>(data), size);
    if (bytes.size() >= 8) {
        cavesim::Fnv1a64 h;
        h.add(bytes.data(), bytes.size() - 8);
        const std::uint64_t v = h.value();
        std::memcpy(bytes.data() + bytes.size() - 8, &v, 8);
    }
    try {
        (void)cavesim::app::decodeState(bytes, "fuzz.cavesim", cavesim::Dims{}, std::size_t(1) << 16);
    } catch (const cavesim::InputError&) {
    }
    return 0;
}
