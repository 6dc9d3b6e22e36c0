// Texture files of the msmcl CLI in any of its containers (docs/formats.md): filtered moment
// shadow maps and summed-area tables read from and written to EXR, KTX2 or DDS.
// Rules:
//  - an input's container is recognized by its first bytes, whatever its name;
//  - an output's container is `--out-container`, else its extension (.exr, .ktx2, .dds);
//    an unknown extension without `--out-container`, or one that contradicts it, is a
//    usage_error (exit 2) before any work is done;
//  - outputs that are EXR only (intensities, radiance) must end in .exr;
//  - DDS keeps no metadata: a DDS map of R16G16B16A16_UNORM texels may be msm64 or nlq64 and
//    is refused unless `--format` names one; a DDS table needs `--max-kernel`.
#pragma once

#include "cli/commands.hpp"

#include "io/exr_io.hpp"
#include "io/sat_exr.hpp"

#include <msmcl/formats.hpp>
#include <msmcl/sat.hpp>

#include <cstdint>
#include <optional>
#include <string>

namespace msmcl::cli {

enum class Container { exr, ktx2, dds };

const char* container_name(Container container) noexcept;

/// The container an output file gets: `option` (exr, ktx2, dds; empty = not given), else the
/// extension of `path`. Throws usage_error for an unknown option, an unknown extension
/// without an option, or an option that contradicts a known extension.
Container output_container(const std::string& option, const std::string& path);

/// For outputs that only exist as EXR: throws usage_error unless `path` ends in .exr.
void require_exr_output(const std::string& path);

/// The container of an existing file from its first bytes; input_error naming the file when
/// it cannot be opened or is none of the three.
Container sniff_container(const std::string& path);

/// A filtered map from any container. `format`: what the user said (--format), checked
/// against what the file records; required for DDS files of msm64/nlq64 texels.
io::TextureFile read_texture_file(const std::string& path, std::optional<Format> format);
/// Writes a filtered map with its record (KTX2 keeps it as key/value data, DDS drops it).
/// `array`: a texture array even of one layer (KTX2 layerCount 1); a texture of several
/// layers is always one. EXR holds one 2D map: an array there is a usage_error.
void write_texture_file(const std::string& path, Container container, const Texture& texture,
                        const io::TextureInfo& info, bool array = false);

/// A summed-area table from any container. `max_kernel`: what the user said
/// (--max-kernel), checked against what the file records; required for DDS files.
io::SatFile read_sat_file(const std::string& path, std::optional<std::uint32_t> max_kernel);
/// Writes a table as write_texture_file writes a map (`array` likewise).
void write_sat_file(const std::string& path, Container container, const SatTable& table, const io::SatInfo& info,
                    bool array = false);

/// A float as the shortest text that reads back to it.
std::string float_text(float value);

} // namespace msmcl::cli
