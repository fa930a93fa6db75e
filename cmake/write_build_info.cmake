# Runs at every build (not only at configure): writes generated/build_info.cpp with the checkout's
# current revision, "-dirty" when tracked files differ from it. configure_file rewrites the file only
# when its text changes, so an unchanged revision recompiles nothing.
# Inputs: -DSOURCE_DIR=... -DTEMPLATE=... -DOUTPUT=... -DPROJECT_VERSION=...
execute_process(COMMAND git rev-parse --short=12 HEAD WORKING_DIRECTORY ${SOURCE_DIR}
                OUTPUT_VARIABLE VPM_GIT_REVISION OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET
                RESULT_VARIABLE rev_result)
if(NOT rev_result EQUAL 0 OR NOT VPM_GIT_REVISION)
  set(VPM_GIT_REVISION "unknown")
else()
  execute_process(COMMAND git status --porcelain --untracked-files=no WORKING_DIRECTORY ${SOURCE_DIR}
                  OUTPUT_VARIABLE changes OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(changes)
    string(APPEND VPM_GIT_REVISION "-dirty")
  endif()
endif()
configure_file(${TEMPLATE} ${OUTPUT} @ONLY)
