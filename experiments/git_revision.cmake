# Writes OUT, a header that defines HRAD_GIT_REVISION as `git describe --always --dirty`
# of the source tree SRC ("unknown" outside a git checkout). Run at every build (the
# hrad_git_revision target), it rewrites OUT only when the revision changed, so that
# `hrad --version` and every stats.json name the revision built, not the one configured.
execute_process(
  COMMAND git describe --always --dirty
  WORKING_DIRECTORY ${SRC}
  OUTPUT_VARIABLE revision
  OUTPUT_STRIP_TRAILING_WHITESPACE
  ERROR_QUIET
  RESULT_VARIABLE result)
if(NOT result EQUAL 0 OR revision STREQUAL "")
  set(revision "unknown")
endif()
set(text "#define HRAD_GIT_REVISION \"${revision}\"\n")
set(old "")
if(EXISTS ${OUT})
  file(READ ${OUT} old)
endif()
if(NOT old STREQUAL text)
  file(WRITE ${OUT} "${text}")
endif()
