# The python_install test: installs the Python component of BUILD_DIR into PREFIX, then
# imports msmcl from PREFIX/PACKAGE_DIR alone (a clean environment, outside the build tree)
# and lists the devices, as a user would after `cmake --install`.
file(REMOVE_RECURSE ${PREFIX})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${PREFIX} --component python
                RESULT_VARIABLE result)
if(result)
  message(FATAL_ERROR "cmake --install failed: ${result}")
endif()
if(NOT EXISTS ${PREFIX}/${PACKAGE_DIR}/msmcl/__init__.pyi)
  message(FATAL_ERROR "the stub is not installed in ${PREFIX}/${PACKAGE_DIR}/msmcl")
endif()
execute_process(
  COMMAND ${CMAKE_COMMAND} -E env --unset=PYTHONPATH PYTHONPATH=${PREFIX}/${PACKAGE_DIR} PYTHONDONTWRITEBYTECODE=1
          ${PYTHON} -c "import msmcl, os; assert msmcl.__file__.startswith(os.environ['PYTHONPATH']), msmcl.__file__; print(msmcl.__file__); print(msmcl.devices())"
  WORKING_DIRECTORY ${PREFIX}
  RESULT_VARIABLE result)
if(result)
  message(FATAL_ERROR "import msmcl from ${PREFIX}/${PACKAGE_DIR} failed: ${result}")
endif()
file(REMOVE_RECURSE ${PREFIX})
