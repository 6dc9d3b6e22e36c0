# ctest script: the core library links no file-format library. File I/O (OpenEXR, libpng,
# JSON) lives in msmcl_io, which the CLI, tools, bench and tests link; libmsmcl.so must
# need OpenCL and the C/C++ runtime only.
#   cmake -DREADELF=<readelf> -DLIBRARY=<libmsmcl.so> -P core_dependencies.cmake
execute_process(COMMAND ${READELF} -d ${LIBRARY} OUTPUT_VARIABLE dynamic RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "${LIBRARY}: readelf -d failed (${status})")
endif()
string(REGEX MATCHALL "NEEDED[^\n]*\\[[^]]*\\]" needed "${dynamic}")
if(NOT needed MATCHES "libOpenCL")
  message(FATAL_ERROR "${LIBRARY}: no NEEDED entry for libOpenCL (readelf output unexpected)")
endif()
foreach(entry IN LISTS needed)
  if(entry MATCHES "OpenEXR|Imath|Iex|IlmThread|libpng|libz|json")
    message(FATAL_ERROR "${LIBRARY}: links a file-format library: ${entry}")
  endif()
  message(STATUS "${entry}")
endforeach()
