# Fails when a file of the source tree refers to material outside the repository: notes
# that are not in it, unnamed design documents, numbered tickets or seed texts. Comments
# cite docs/ or a paper by author, venue and section instead (docs/README.md).
#   cmake -DSOURCE_DIR=<tree> -P check_self_contained.cmake
if(NOT SOURCE_DIR)
  message(FATAL_ERROR "check_self_contained: pass -DSOURCE_DIR=<tree>")
endif()

# The forbidden references. Words are assembled from pieces so that this file does not
# match itself.
set(upper_word "SP")
string(APPEND upper_word "EC")
set(patterns
  "\\.\\./shared"
  "/work/(shared|brief)"
  "(^|[^A-Za-z_])${upper_word}([^A-Za-z_]|$)"
  "[Ss]eed 00[0-9]"
  "seed[s]/"
  "[Ii]ssue #?[0-9]"
  "[Tt]ask #?[0-9]"
  "(POCL|GPU)-NOTE[S]"
  "ARCHITECTURE\\.md")
list(JOIN patterns "|" forbidden)

# Everything but build trees, outputs, version control and binary data.
file(GLOB top_entries LIST_DIRECTORIES true RELATIVE "${SOURCE_DIR}" "${SOURCE_DIR}/*" "${SOURCE_DIR}/.*")
set(files)
foreach(entry IN LISTS top_entries)
  if(entry MATCHES "^(build.*|out|q|q-large|\\.git|\\.cache|\\.ccache|Testing)$")
    continue()
  endif()
  if(IS_DIRECTORY "${SOURCE_DIR}/${entry}")
    file(GLOB_RECURSE found RELATIVE "${SOURCE_DIR}" "${SOURCE_DIR}/${entry}/*")
    list(APPEND files ${found})
  else()
    list(APPEND files "${entry}")
  endif()
endforeach()

set(failures 0)
foreach(file IN LISTS files)
  if(file MATCHES "\\.(exr|png|ktx2|dds|ply|bin|o|a|so)$")
    continue()
  endif()
  file(STRINGS "${SOURCE_DIR}/${file}" hits REGEX "${forbidden}")
  foreach(hit IN LISTS hits)
    message("${file}: refers outside the repository: ${hit}")
    math(EXPR failures "${failures} + 1")
  endforeach()
endforeach()
list(LENGTH files checked)
if(failures GREATER 0)
  message(FATAL_ERROR "${failures} reference(s) outside the repository in ${checked} files; cite docs/ or a paper instead (docs/README.md)")
endif()
message(STATUS "${checked} files checked, no reference outside the repository")
