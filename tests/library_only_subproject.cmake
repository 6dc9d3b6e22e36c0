# ctest script: msmcl as an engine's subproject (add_subdirectory, as FetchContent does) builds
# its library alone by default, with OpenCL as its only package: OpenEXR, libpng, Boost and
# GoogleTest are hidden (CMAKE_DISABLE_FIND_PACKAGE_<name>, pkg-config disabled with them), so
# a lookup of any of them fails the configure step. No test, tool, bench, example or CLI
# target may exist, and the engine's C program (examples/engine.c, at OpenCL 3.0) builds
# warning-free against msmcl::msmcl.
#   cmake -DSOURCE_DIR=<msmcl> -DWORK_DIR=<scratch> -DC_COMPILER=<cc> -DCXX_COMPILER=<c++>
#         [-DLAUNCHER=<ccache>] -P library_only_subproject.cmake
foreach(variable SOURCE_DIR WORK_DIR C_COMPILER CXX_COMPILER)
  if(NOT ${variable})
    message(FATAL_ERROR "library_only_subproject: pass -D${variable}=...")
  endif()
endforeach()

file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR}/engine)
file(WRITE ${WORK_DIR}/engine/CMakeLists.txt "cmake_minimum_required(VERSION 3.21)
project(engine LANGUAGES C CXX)
add_subdirectory(\"${SOURCE_DIR}\" msmcl)
foreach(target msmcl_io msmcl_cli msmcl-scene msmcl-preview msmcl-bench msmcl_reference filter_test install_test
               msmcl_example_engine msmcl-vulkan)
  if(TARGET \${target})
    message(FATAL_ERROR \"the msmcl subproject defines \${target}: only its library should be built by default\")
  endif()
endforeach()
add_executable(engine \"${SOURCE_DIR}/examples/engine.c\")
set_target_properties(engine PROPERTIES C_STANDARD 99 C_STANDARD_REQUIRED ON)
target_compile_definitions(engine PRIVATE CL_TARGET_OPENCL_VERSION=300)
target_compile_options(engine PRIVATE -Wall -Wextra -Werror)
target_link_libraries(engine PRIVATE msmcl::msmcl)
")

set(hidden "")
foreach(package OpenEXR PNG ZLIB PkgConfig Boost GTest Imath)
  list(APPEND hidden -DCMAKE_DISABLE_FIND_PACKAGE_${package}=ON)
endforeach()
set(launchers "")
if(LAUNCHER)
  set(launchers -DCMAKE_C_COMPILER_LAUNCHER=${LAUNCHER} -DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER})
endif()
execute_process(
  COMMAND ${CMAKE_COMMAND} -S ${WORK_DIR}/engine -B ${WORK_DIR}/build -DCMAKE_BUILD_TYPE=Release
          -DCMAKE_C_COMPILER=${C_COMPILER} -DCMAKE_CXX_COMPILER=${CXX_COMPILER} ${launchers} ${hidden}
  RESULT_VARIABLE status OUTPUT_VARIABLE output ERROR_VARIABLE output)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "library-only configure failed:\n${output}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK_DIR}/build --target engine --parallel 2
                RESULT_VARIABLE status OUTPUT_VARIABLE output ERROR_VARIABLE output)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "library-only build failed:\n${output}")
endif()
message(STATUS "msmcl built as a subproject with OpenCL alone; the engine links msmcl::msmcl")
file(REMOVE_RECURSE ${WORK_DIR})
