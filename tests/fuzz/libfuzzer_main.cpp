// libFuzzer's entry point (clang's -fsanitize=fuzzer); see tools/fuzz.sh.
#include "graph_fuzz_target.hpp"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    skygraph::fuzz::runOneInput({reinterpret_cast<const char*>(data), size});
    return 0;
}
