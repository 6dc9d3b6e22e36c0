// msmcl-kernel-variants: writes every program variant the library builds, assembled by the
// library's own code (defines, includes, build options), for offline GPU compilers:
//   msmcl-kernel-variants OUT_DIR [--full]
// OUT_DIR/v<N>.cl holds variant N's source, OUT_DIR/variants.json describes them all
// (operation, file, defines, build options, kernels and whether `automatic` can pick each
// on a GPU). scripts/gpu_compile_report.py compiles them.
#include "ops/kernel_variants.hpp"
#include "runtime/kernel_sources.hpp"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

int main(int argc, char** argv) {
    std::string out_dir;
    bool full = false;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--full") == 0) full = true;
        else if (argv[i][0] != '-' && out_dir.empty()) out_dir = argv[i];
        else {
            std::cerr << "usage: msmcl-kernel-variants OUT_DIR [--full]\n";
            return 2;
        }
    }
    if (out_dir.empty()) {
        std::cerr << "usage: msmcl-kernel-variants OUT_DIR [--full]\n";
        return 2;
    }
    try {
        std::filesystem::create_directories(out_dir);
        nlohmann::json list = nlohmann::json::array();
        int index = 0;
        for (const msmcl::detail::KernelVariant& variant : msmcl::detail::kernel_variants(full)) {
            // The source exactly as ContextImpl::kernel hands it to clCreateProgramWithSource.
            const std::string name = "v" + std::to_string(index++) + ".cl";
            std::ofstream(std::filesystem::path(out_dir) / name, std::ios::binary)
                << msmcl::detail::kernel_source(variant.file, variant.defines).text;
            nlohmann::json kernels = nlohmann::json::array();
            for (const auto& kernel : variant.kernels) kernels.push_back({{"name", kernel.name}, {"gpu_path", kernel.gpu_path}});
            list.push_back({{"source", name},
                            {"operation", variant.operation},
                            {"file", variant.file},
                            {"defines", variant.defines},
                            {"options", msmcl::detail::base_build_options},
                            {"kernels", kernels},
                            {"note", variant.note}});
        }
        std::ofstream(std::filesystem::path(out_dir) / "variants.json") << list.dump(1) << '\n';
        std::cout << index << " variants in " << out_dir << "\n";
    } catch (const std::exception& e) {
        std::cerr << "msmcl-kernel-variants: " << out_dir << ": " << e.what() << "\n";
        return 1;
    }
    return 0;
}
