# The bash completion of the msmcl CLI and the per-command section of its man page, both from
# the CLI's own help texts (`msmcl --help`, `msmcl COMMAND --help`), so that neither can drift
# from the options the CLI has. Run at build time by CMakeLists.txt:
#   cmake -DCLI=<msmcl> -DCOMPLETION=<out.bash> -DMAN_INCLUDE=<out.h2m> -P cli_docs.cmake
# The man page itself is help2man's rendering of `msmcl --help` with MAN_INCLUDE added.
foreach(variable CLI COMPLETION MAN_INCLUDE)
  if(NOT ${variable})
    message(FATAL_ERROR "cli_docs: pass -D${variable}=...")
  endif()
endforeach()

function(help_of output_variable)
  execute_process(COMMAND ${CLI} ${ARGN} --help RESULT_VARIABLE status OUTPUT_VARIABLE text ERROR_VARIABLE errors)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "cli_docs: '${CLI} ${ARGN} --help' failed (${status}): ${errors}")
  endif()
  set(${output_variable} "${text}" PARENT_SCOPE)
endfunction()

# The option names of a CLI11 help text: the lines "  -o,--output-dir DIR   text" of its
# "Options:" block, names up to the first blank.
function(options_of output_variable text)
  set(names "")
  string(REPLACE ";" "," text "${text}")
  string(REPLACE "\n" ";" lines "${text}")
  foreach(line IN LISTS lines)
    if(line MATCHES "^  +(-[^ ]+)")
      string(REPLACE "," ";" spelled "${CMAKE_MATCH_1}")
      foreach(name IN LISTS spelled)
        if(name MATCHES "^--?[A-Za-z]")
          list(APPEND names ${name})
        endif()
      endforeach()
    endif()
  endforeach()
  list(REMOVE_DUPLICATES names)
  set(${output_variable} "${names}" PARENT_SCOPE)
endfunction()

help_of(top_help)
options_of(global_options "${top_help}")
# The commands: the lines of the "Subcommands:" block.
string(REGEX REPLACE ".*\nSubcommands:\n" "" commands_block "${top_help}")
string(REGEX REPLACE "\n\n.*" "" commands_block "${commands_block}")
string(REPLACE "\n" ";" command_lines "${commands_block}")
set(commands "")
foreach(line IN LISTS command_lines)
  if(line MATCHES "^  ([a-z]+)")
    list(APPEND commands ${CMAKE_MATCH_1})
  endif()
endforeach()
if(NOT commands)
  message(FATAL_ERROR "cli_docs: no subcommands in '${CLI} --help':\n${top_help}")
endif()

# Roff-safe text for the man page: backslashes doubled, no line read as a request.
function(roff output_variable text)
  string(REPLACE "\\" "\\e" text "${text}")
  string(REGEX REPLACE "(^|\n)([.'])" "\\1\\\\&\\2" text "${text}")
  set(${output_variable} "${text}" PARENT_SCOPE)
endfunction()

set(cases "")
set(man "[COMMANDS]\nEach command's own help (msmcl COMMAND --help).\n")
foreach(command IN LISTS commands)
  help_of(command_help ${command})
  options_of(command_options "${command_help}")
  # The global options may follow the command too.
  list(APPEND command_options ${global_options})
  list(REMOVE_DUPLICATES command_options)
  string(REPLACE ";" " " command_options "${command_options}")
  string(APPEND cases "    ${command}) words=\"${command_options}\" ;;\n")
  # The exit codes once, in the page's own part.
  string(REGEX REPLACE "\nExit codes:[^\n]*\n*$" "\n" command_help "${command_help}")
  roff(text "${command_help}")
  string(APPEND man ".SS msmcl ${command}\n.nf\n${text}.fi\n")
endforeach()
string(REPLACE ";" " " command_words "${commands}")
string(REPLACE ";" " " global_words "${global_options}")
string(REPLACE ";" "|" command_pattern "${commands}")

file(WRITE ${COMPLETION} "# bash completion of msmcl, generated from its --help texts (cmake/cli_docs.cmake).
# Completes the commands, the options of the command on the line, and files elsewhere.
_msmcl() {
  local cur=\${COMP_WORDS[COMP_CWORD]} command= i words
  for ((i = 1; i < COMP_CWORD; i++)); do
    case \${COMP_WORDS[i]} in
      ${command_pattern}) command=\${COMP_WORDS[i]}; break ;;
    esac
  done
  case \$command in
    '') words=\"${command_words}\"; [[ \$cur == -* ]] && words=\"${global_words}\" ;;
${cases}  esac
  COMPREPLY=()
  # A command's positional arguments are files: left to bash's file completion.
  if [[ -z \$command || \$cur == -* ]]; then
    COMPREPLY=(\$(compgen -W \"\$words\" -- \"\$cur\"))
  fi
}
complete -o default -o bashdefault -F _msmcl msmcl
")
file(WRITE ${MAN_INCLUDE} "${man}")
