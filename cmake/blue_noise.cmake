# The blue-noise textures of the dithered lookup (docs/math.md), generated at build time by
# void-and-cluster (host/bluenoise/) and compiled into the library
# (host/shading/blue_noise.cpp includes generated/blue_noise_table.inc; without this step
# the library generates the same table on first use). Include after msmcl_objects is defined.
include_guard(GLOBAL)
add_executable(msmcl-blue-noise ${PROJECT_SOURCE_DIR}/host/bluenoise/generate_table.cpp)
target_include_directories(msmcl-blue-noise PRIVATE ${PROJECT_SOURCE_DIR}/host)
target_link_libraries(msmcl-blue-noise PRIVATE Threads::Threads)
target_compile_options(msmcl-blue-noise PRIVATE -Wall -Wextra)
# Even in a Debug build the generator runs optimized (128 void-and-cluster runs).
target_compile_options(msmcl-blue-noise PRIVATE $<$<CONFIG:Debug>:-O2>)

set(MSMCL_BLUE_NOISE_TABLE ${PROJECT_BINARY_DIR}/generated/blue_noise_table.inc)
add_custom_command(
  OUTPUT ${MSMCL_BLUE_NOISE_TABLE}
  COMMAND msmcl-blue-noise --output ${MSMCL_BLUE_NOISE_TABLE}
  DEPENDS msmcl-blue-noise
  COMMENT "Generating the blue-noise textures (void-and-cluster, 64 x 64^2 x 2)" VERBATIM)
# Generated before the library's sources compile; blue_noise.cpp recompiles when it changes.
target_sources(msmcl_objects PRIVATE ${MSMCL_BLUE_NOISE_TABLE})
set_source_files_properties(${PROJECT_SOURCE_DIR}/host/shading/blue_noise.cpp PROPERTIES
  OBJECT_DEPENDS ${MSMCL_BLUE_NOISE_TABLE})
