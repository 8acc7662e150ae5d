# Runs one corpus replay with TMPDIR set to an empty folder of its own, and fails if the replay leaves
# anything there: each fuzz input's work folder (fuzz_input_file.hpp) must be gone when the process
# ends. Until 2026-12-07 every replay left its folder in /tmp, 13 per run of the test suite.
# cmake -DREPLAY=<replay_NAME> -DCORPUS=<folder> -DTMP=<empty folder to use> -P check_work_dir_removed.cmake
file(REMOVE_RECURSE "${TMP}")
file(MAKE_DIRECTORY "${TMP}")
execute_process(COMMAND "${CMAKE_COMMAND}" -E env "TMPDIR=${TMP}" "${REPLAY}" "${CORPUS}"
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${REPLAY} ${CORPUS} failed (${rc}): ${err}")
endif()
file(GLOB left "${TMP}/*")
if(left)
  message(FATAL_ERROR "${REPLAY} left behind in TMPDIR: ${left}")
endif()
file(REMOVE_RECURSE "${TMP}")
