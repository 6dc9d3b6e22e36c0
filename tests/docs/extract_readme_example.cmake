# Writes the C++ block that follows the `readme_example` marker in README.md to a file, so
# that the test `readme_example` compiles and runs exactly what the README prints.
#   cmake -DREADME=<README.md> -DOUTPUT=<file.cpp> -P extract_readme_example.cmake
if(NOT README OR NOT OUTPUT)
  message(FATAL_ERROR "extract_readme_example: pass -DREADME=<README.md> -DOUTPUT=<file.cpp>")
endif()

# The text after the first `needle` of `text`, or a failure that says what is missing.
function(text_after text needle missing result)
  string(FIND "${text}" "${needle}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "${README}: ${missing}")
  endif()
  string(LENGTH "${needle}" length)
  math(EXPR at "${at} + ${length}")
  string(SUBSTRING "${text}" ${at} -1 rest)
  set(${result} "${rest}" PARENT_SCOPE)
endfunction()

# The marker comment, then the next fenced cpp block, up to its closing fence.
file(READ "${README}" text)
text_after("${text}" "<!-- readme_example:" "no <!-- readme_example: ... --> marker before the example" text)
text_after("${text}" "\n```cpp\n" "no ```cpp block after the readme_example marker" text)
string(FIND "${text}" "\n```" close)
if(close EQUAL -1)
  message(FATAL_ERROR "${README}: the readme_example block is not closed")
endif()
math(EXPR length "${close} + 1")
string(SUBSTRING "${text}" 0 ${length} program)

# Rewrite the file only when the block changed, so that an unrelated README edit rebuilds nothing.
if(EXISTS "${OUTPUT}")
  file(READ "${OUTPUT}" old)
  if(old STREQUAL program)
    return()
  endif()
endif()
file(WRITE "${OUTPUT}" "${program}")
