# The regular test suite replays every fuzz corpus (tests/fuzz/corpus/<name>/) through its reader
# under AddressSanitizer and UBSan, with the compiler of the build (GCC is enough: no libFuzzer).
#
# The libraries are compiled a second time, instrumented: grainscale_dem_asan etc. are copies of
# grainscale_dem etc. (same sources, include folders and dependencies, read from the targets
# themselves, so a file added to a stage is picked up) at -O0 (half the compile time of -O1; the
# corpora run in seconds either way) with the sanitizers and assertions on.
# Each fuzz target is linked with replay_main.cpp instead of libFuzzer into replay_<name>, and CTest
# runs it as sanitized_corpus_<name> (label "sanitizer"). Off with -DGRAINSCALE_SANITIZED_CORPORA=OFF;
# not made in a -DGRAINSCALE_FUZZ=ON build, where everything is instrumented already and the
# fuzz_corpus_<name> tests do the same.
include(CheckCXXSourceCompiles)
# Imported targets found in a stage's own folder are not visible here: find them again.
find_package(ZLIB REQUIRED)
include(${CMAKE_CURRENT_LIST_DIR}/targets.cmake)

set(GRAINSCALE_SANITIZER_FLAGS -fsanitize=address,undefined,float-cast-overflow -fno-sanitize-recover=all
    -fno-omit-frame-pointer)
set(CMAKE_REQUIRED_FLAGS "-fsanitize=address,undefined,float-cast-overflow")
set(CMAKE_REQUIRED_LINK_OPTIONS "-fsanitize=address,undefined")
check_cxx_source_compiles("int main() { return 0; }" GRAINSCALE_HAVE_SANITIZERS)
unset(CMAKE_REQUIRED_FLAGS)
unset(CMAKE_REQUIRED_LINK_OPTIONS)
if(NOT GRAINSCALE_HAVE_SANITIZERS)
  message(WARNING "The compiler cannot build with -fsanitize=address,undefined (libasan/libubsan missing?): "
                  "the sanitized corpus replay (tests/fuzz/sanitized_replay.cmake) is left out")
  return()
endif()

# grainscale_X -> grainscale_X_asan, instrumented; its grainscale_* dependencies become their copies.
function(grainscale_sanitized_copy target)
  if(TARGET ${target}_asan)
    return()
  endif()
  get_target_property(sources ${target} SOURCES)
  get_target_property(source_dir ${target} SOURCE_DIR)
  set(absolute)
  foreach(s ${sources})
    if(IS_ABSOLUTE "${s}")
      list(APPEND absolute "${s}")
    else()
      list(APPEND absolute "${source_dir}/${s}")
    endif()
  endforeach()
  add_library(${target}_asan STATIC ${absolute})
  foreach(property INCLUDE_DIRECTORIES COMPILE_DEFINITIONS)
    get_target_property(value ${target} ${property})
    if(value)
      set_property(TARGET ${target}_asan PROPERTY ${property} "${value}")
    endif()
  endforeach()
  foreach(property INTERFACE_INCLUDE_DIRECTORIES INTERFACE_COMPILE_DEFINITIONS)
    get_target_property(value ${target} ${property})
    if(value)
      set_property(TARGET ${target}_asan PROPERTY ${property} "${value}")
    endif()
  endforeach()
  get_target_property(libraries ${target} LINK_LIBRARIES)
  set(copied)
  foreach(l ${libraries})
    if(l MATCHES "^grainscale_")
      grainscale_sanitized_copy(${l})
      list(APPEND copied ${l}_asan)
    else()
      list(APPEND copied ${l})
    endif()
  endforeach()
  target_link_libraries(${target}_asan PUBLIC ${copied})
  # -O0 after the build type's -O3 wins; assertions on (-UNDEBUG after -DNDEBUG).
  target_compile_options(${target}_asan PRIVATE ${GRAINSCALE_SANITIZER_FLAGS} -O0 -UNDEBUG)
  target_link_options(${target}_asan INTERFACE -fsanitize=address,undefined)
endfunction()

set(corpus_root ${CMAKE_CURRENT_LIST_DIR}/corpus)
# Every replay stops at its first sanitizer report.
set(replay_environment
    "ASAN_OPTIONS=detect_leaks=1:abort_on_error=0:halt_on_error=1;UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1;OMP_WAIT_POLICY=passive")
foreach(entry ${GRAINSCALE_FUZZ_TARGETS})
  string(REPLACE ":" ";" entry "${entry}")
  list(GET entry 0 name)
  list(GET entry 1 library)
  grainscale_sanitized_copy(${library})
  add_executable(replay_${name} ${CMAKE_CURRENT_LIST_DIR}/replay_main.cpp ${CMAKE_CURRENT_LIST_DIR}/fuzz_${name}.cpp)
  target_link_libraries(replay_${name} PRIVATE ${library}_asan)
  target_compile_options(replay_${name} PRIVATE ${GRAINSCALE_SANITIZER_FLAGS} -O0 -UNDEBUG)
  target_compile_definitions(replay_${name} PRIVATE GRAINSCALE_FUZZ_CORPUS="${corpus_root}")
  add_test(NAME sanitized_corpus_${name} COMMAND replay_${name} ${corpus_root}/${name})
  set_tests_properties(sanitized_corpus_${name} PROPERTIES LABELS sanitizer ENVIRONMENT "${replay_environment}")
endforeach()

# The replays remove their work folders (tests/fuzz/check_work_dir_removed.cmake).
add_test(NAME sanitized_corpus_work_dir_removed
         COMMAND ${CMAKE_COMMAND} -DREPLAY=$<TARGET_FILE:replay_materials> -DCORPUS=${corpus_root}/materials
                 -DTMP=${CMAKE_CURRENT_BINARY_DIR}/work_dir_removed_tmp -P ${CMAKE_CURRENT_LIST_DIR}/check_work_dir_removed.cmake)
set_tests_properties(sanitized_corpus_work_dir_removed PROPERTIES LABELS sanitizer ENVIRONMENT "${replay_environment}")
