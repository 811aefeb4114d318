// libFuzzer target: any bytes as state.cavesim. The reader must refuse what it did not write with
// InputError and never read out of bounds or allocate beyond the grid it accepts.
#include <cstddef>
#include <cstdint>
#include <string>

#include "app/state_file.h"
#include "core/error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string bytes(reinterpret_cast<const char*>(data), size);
    try {
        (void)cavesim::app::decodeState(bytes, "fuzz.cavesim", cavesim::Dims{}, std::size_t(1) << 16);
    } catch (const cavesim::InputError&) {
    }
    return 0;
}
