// libFuzzer's entry point for the glTF loader (clang's -fsanitize=fuzzer); see tools/fuzz.sh.
#include "gltf_fuzz_target.hpp"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    skygraph::fuzz::runOneGltfInput({reinterpret_cast<const char*>(data), size});
    return 0;
}
