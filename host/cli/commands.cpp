#include "cli/commands.hpp"

namespace msmcl::cli {

DeviceSelection GlobalArguments::selection() const {
    DeviceSelection selection;
    selection.device = device;
    // A --device that matches nothing is an error, not a silent fallback.
    selection.strict = !device.empty();
    return selection;
}

[[noreturn]] void rethrow_with_file(const std::string& path, const input_error& e) {
    throw input_error(path + ": " + e.what());
}

} // namespace msmcl::cli
