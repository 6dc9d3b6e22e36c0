# Generates msm.hlsl from msm.glsl (itself generated: docs/shaders.md): the function bodies
# are shared text, only type names, a few intrinsics and texel fetches differ. Usage:
#   cmake -DINPUT=<build>/shaders/msm.glsl -DOUTPUT=<build>/shaders/msm.hlsl -P cmake/glsl_to_hlsl.cmake
# tests/shaders_test.cpp regenerates it and requires the built file to be identical.
if(NOT INPUT OR NOT OUTPUT)
  message(FATAL_ERROR "glsl_to_hlsl.cmake: set INPUT and OUTPUT")
endif()
file(READ ${INPUT} glsl)

# The GLSL file's header comment is replaced; the code starts at its include guard.
string(FIND "${glsl}" "#ifndef MSM_GLSL" body_start)
if(body_start LESS 0)
  message(FATAL_ERROR "glsl_to_hlsl.cmake: ${INPUT} has no '#ifndef MSM_GLSL'")
endif()
string(SUBSTRING "${glsl}" ${body_start} -1 body)

# Keep identifiers whole: a token is replaced only between non-identifier characters.
set(edge "([^A-Za-z0-9_])")
macro(replace_token from to)
  string(REGEX REPLACE "${edge}${from}${edge}" "\\1${to}\\2" body "${body}")
  # A second pass catches tokens whose leading edge was the previous match's trailing edge.
  string(REGEX REPLACE "${edge}${from}${edge}" "\\1${to}\\2" body "${body}")
endmacro()

# texelFetch(t, ivec2(x, y), 0) -> t.Load(int3(x, y, 0))
string(REGEX REPLACE "texelFetch\\(([A-Za-z_0-9]+), ivec2\\(([^()]*)\\), 0\\)" "\\1.Load(int3(\\2, 0))" body "${body}")
# texelFetch(t, ivec3(x, y, layer), 0) -> t.Load(int4(x, y, layer, 0)) (texture arrays)
string(REGEX REPLACE "texelFetch\\(([A-Za-z_0-9]+), ivec3\\(([^()]*)\\), 0\\)" "\\1.Load(int4(\\2, 0))" body "${body}")
replace_token(MSM_GLSL MSM_HLSL)
replace_token(usampler2DArray "Texture2DArray<uint4>")
replace_token(sampler2DArray "Texture2DArray<float4>")
replace_token(usampler2D "Texture2D<uint4>")
replace_token(sampler2D "Texture2D<float4>")
replace_token(uvec4 uint4)
replace_token(ivec2 int2)
replace_token(vec4 float4)
replace_token(vec2 float2)
replace_token(floatBitsToUint asuint)
replace_token(uintBitsToFloat asfloat)

set(header "// msmcl shader functions (HLSL, Shader Model 5+): GENERATED from msm.glsl by
// cmake/glsl_to_hlsl.cmake; msm.glsl is generated from kernels/*.clh and shaders/msm.glsl.in
// (docs/shaders.md): edit those and rebuild, or run scripts/generate-shaders.sh.
// Same functions, names and operations as the GLSL file (see its header for the texture
// formats, how to sample them and the accuracy notes); textures are Texture2D<float4> /
// Texture2D<uint4> (Texture2DArray for the _array lookups) read with Load, so every sampler
// state works.
")
file(WRITE ${OUTPUT}.tmp "${header}${body}")
file(RENAME ${OUTPUT}.tmp ${OUTPUT})
