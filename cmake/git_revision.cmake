# Run at every build (the grainscale_git_revision target): writes OUT with the source tree's
# `git describe`, touching it only when the text changes, so an unchanged tree rebuilds nothing.
# Usage: cmake -DSOURCE_DIR=... -DOUT=... -P git_revision.cmake
execute_process(COMMAND git describe --always --dirty --tags
                WORKING_DIRECTORY ${SOURCE_DIR}
                OUTPUT_VARIABLE GRAINSCALE_GIT OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(NOT GRAINSCALE_GIT)
  set(GRAINSCALE_GIT "unknown")
endif()
set(text "// Generated at build time by cmake/git_revision.cmake; do not edit.\n#include \"grainscale_version.hpp\"\nnamespace grainscale {\nconst char* const git_revision = \"${GRAINSCALE_GIT}\";\n}  // namespace grainscale\n")
if(EXISTS ${OUT})
  file(READ ${OUT} old)
else()
  set(old "")
endif()
if(NOT old STREQUAL text)
  file(WRITE ${OUT} "${text}")
endif()
