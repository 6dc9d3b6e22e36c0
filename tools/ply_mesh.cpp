#include "ply_mesh.hpp"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace msmcl::data {
namespace {

enum class Scalar { int8, uint8, int16, uint16, int32, uint32, float32, float64 };

struct Property {
    std::string name;
    Scalar type = Scalar::float32;
    bool is_list = false;
    Scalar count_type = Scalar::uint8;
};

struct Element {
    std::string name;
    std::size_t count = 0;
    std::vector<Property> properties;
};

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
    throw std::runtime_error(path + ": " + problem);
}

Scalar parse_scalar(const std::string& path, const std::string& name) {
    if (name == "char" || name == "int8") return Scalar::int8;
    if (name == "uchar" || name == "uint8") return Scalar::uint8;
    if (name == "short" || name == "int16") return Scalar::int16;
    if (name == "ushort" || name == "uint16") return Scalar::uint16;
    if (name == "int" || name == "int32") return Scalar::int32;
    if (name == "uint" || name == "uint32") return Scalar::uint32;
    if (name == "float" || name == "float32") return Scalar::float32;
    if (name == "double" || name == "float64") return Scalar::float64;
    fail(path, "unknown PLY property type '" + name + "'");
}

std::size_t scalar_bytes(Scalar type) {
    switch (type) {
    case Scalar::int8:
    case Scalar::uint8: return 1;
    case Scalar::int16:
    case Scalar::uint16: return 2;
    case Scalar::int32:
    case Scalar::uint32:
    case Scalar::float32: return 4;
    case Scalar::float64: return 8;
    }
    return 0;
}

/// Reads scalar values one at a time from either encoding.
class ValueReader {
public:
    ValueReader(const std::string& path, std::istream& in, bool binary) : path_(path), in_(in), binary_(binary) {}

    double next(Scalar type) {
        if (!binary_) {
            double value;
            if (!(in_ >> value)) fail(path_, "truncated or malformed ascii data");
            return value;
        }
        unsigned char bytes[8];
        const std::size_t size = scalar_bytes(type);
        if (!in_.read(reinterpret_cast<char*>(bytes), static_cast<std::streamsize>(size)))
            fail(path_, "truncated binary data");
        // Little-endian to host: assemble the bits explicitly.
        std::uint64_t bits = 0;
        for (std::size_t i = 0; i < size; ++i) bits |= static_cast<std::uint64_t>(bytes[i]) << (8 * i);
        switch (type) {
        case Scalar::int8: return static_cast<std::int8_t>(bits);
        case Scalar::uint8: return static_cast<std::uint8_t>(bits);
        case Scalar::int16: return static_cast<std::int16_t>(bits);
        case Scalar::uint16: return static_cast<std::uint16_t>(bits);
        case Scalar::int32: return static_cast<std::int32_t>(bits);
        case Scalar::uint32: return static_cast<std::uint32_t>(bits);
        case Scalar::float32: {
            const std::uint32_t word = static_cast<std::uint32_t>(bits);
            float value;
            std::memcpy(&value, &word, sizeof value);
            return value;
        }
        case Scalar::float64: {
            double value;
            std::memcpy(&value, &bits, sizeof value);
            return value;
        }
        }
        return 0;
    }

private:
    const std::string& path_;
    std::istream& in_;
    bool binary_;
};

} // namespace

TriangleMesh read_ply(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(path, "cannot open");

    // Header: format, elements and their properties, up to end_header.
    std::string line;
    if (!std::getline(in, line) || line.substr(0, 3) != "ply") fail(path, "not a PLY file");
    bool binary = false;
    bool have_format = false;
    std::vector<Element> elements;
    while (true) {
        if (!std::getline(in, line)) fail(path, "PLY header has no end_header");
        if (!line.empty() && line.back() == '\r') line.pop_back();
        std::istringstream words(line);
        std::string keyword;
        words >> keyword;
        if (keyword == "end_header") break;
        if (keyword == "comment" || keyword == "obj_info" || keyword.empty()) continue;
        if (keyword == "format") {
            std::string encoding;
            words >> encoding;
            if (encoding == "ascii") binary = false;
            else if (encoding == "binary_little_endian") binary = true;
            else fail(path, "unsupported PLY encoding '" + encoding + "'");
            have_format = true;
        } else if (keyword == "element") {
            Element element;
            words >> element.name >> element.count;
            if (!words) fail(path, "bad element line '" + line + "'");
            elements.push_back(element);
        } else if (keyword == "property") {
            if (elements.empty()) fail(path, "property before any element");
            Property property;
            std::string type;
            words >> type;
            if (type == "list") {
                std::string count_type, item_type;
                words >> count_type >> item_type >> property.name;
                property.is_list = true;
                property.count_type = parse_scalar(path, count_type);
                property.type = parse_scalar(path, item_type);
            } else {
                property.type = parse_scalar(path, type);
                words >> property.name;
            }
            if (!words) fail(path, "bad property line '" + line + "'");
            elements.back().properties.push_back(property);
        }
        // Anything else is treated as a comment: some exporters (e.g. Blender 2.47, which
        // wrote Wuson.ply) leave a bare text line in the header.
    }
    if (!have_format) fail(path, "PLY header has no format line");

    // Body: elements in header order; keep positions and face lists.
    TriangleMesh mesh;
    ValueReader values(path, in, binary);
    for (const Element& element : elements) {
        const bool is_vertex = element.name == "vertex";
        const bool is_face = element.name == "face";
        for (std::size_t item = 0; item < element.count; ++item) {
            Vec3 position{};
            for (const Property& property : element.properties) {
                if (property.is_list) {
                    const double count = values.next(property.count_type);
                    if (count < 0 || count > 1024) fail(path, "implausible list length in element " + element.name);
                    std::vector<int> indices(static_cast<std::size_t>(count));
                    for (int& index : indices) index = static_cast<int>(values.next(property.type));
                    if (is_face && (property.name == "vertex_indices" || property.name == "vertex_index"))
                        for (std::size_t k = 2; k < indices.size(); ++k)
                            mesh.triangles.push_back({indices[0], indices[k - 1], indices[k]});
                } else {
                    const double value = values.next(property.type);
                    if (is_vertex && property.name == "x") position[0] = value;
                    if (is_vertex && property.name == "y") position[1] = value;
                    if (is_vertex && property.name == "z") position[2] = value;
                }
            }
            if (is_vertex) mesh.vertices.push_back(position);
        }
    }

    // Every index must name a vertex.
    for (const auto& triangle : mesh.triangles)
        for (int index : triangle)
            if (index < 0 || static_cast<std::size_t>(index) >= mesh.vertices.size())
                fail(path, "face index " + std::to_string(index) + " out of range");
    if (mesh.triangles.empty()) fail(path, "no faces");
    return mesh;
}

} // namespace msmcl::data
