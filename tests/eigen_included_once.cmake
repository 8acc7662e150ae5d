# Every file includes Eigen through dem/eigen_dense.hpp, which keeps GCC 12's false warnings inside
# Eigen's AVX-512 code out of the build (that header says why). A file that includes <Eigen/...>
# directly brings them back: 8 to 30 a file, burying a real warning. Run by ctest (tests/CMakeLists.txt)
# with -DSOURCE_DIR=<the source tree>.
file(GLOB_RECURSE sources RELATIVE "${SOURCE_DIR}"
     "${SOURCE_DIR}/dem/*.?pp" "${SOURCE_DIR}/coarsegrain/*.?pp" "${SOURCE_DIR}/continuum/*.?pp"
     "${SOURCE_DIR}/studies/*.?pp" "${SOURCE_DIR}/tests/*.?pp" "${SOURCE_DIR}/bench/*.?pp")
set(direct "")
foreach(f IN LISTS sources)
  if(f STREQUAL "dem/eigen_dense.hpp")
    continue()
  endif()
  file(STRINGS "${SOURCE_DIR}/${f}" hits REGEX "^[ \t]*#[ \t]*include[ \t]*<Eigen/")
  if(hits)
    list(APPEND direct "${f}")
  endif()
endforeach()
if(direct)
  list(JOIN direct ", " names)
  message(FATAL_ERROR "${names}: include \"dem/eigen_dense.hpp\" instead of <Eigen/...> (dem/eigen_dense.hpp says why)")
endif()
list(LENGTH sources count)
message(STATUS "${count} files checked: Eigen is included through dem/eigen_dense.hpp only")
