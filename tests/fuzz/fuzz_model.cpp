// A model file: the safetensors header and shapes, every tensor's values, and the PTv3 config
// in its metadata (no device needed).
#include "nn/ptv3/weights.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto path = pg::fuzz::write_input(data, size, "model.safetensors");
    pg::fuzz::expect_clean(path, [&] {
        const auto file = pg::nn::SafeTensors::load(path);
        for (const auto& [name, info] : file.tensors()) {
            if (info.dtype == "F32" || info.dtype == "F16" || info.dtype == "BF16" || info.dtype == "F64") file.f32(name);
        }
        pg::nn::Ptv3Weights::config_of(file);
    });
    return 0;
}
