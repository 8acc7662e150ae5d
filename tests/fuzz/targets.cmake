# The fuzz targets and the library each one tests (tests/fuzz/README.md). Used by the libFuzzer
# build (tests/fuzz/CMakeLists.txt) and by the sanitized corpus replay of the regular test suite
# (tests/fuzz/sanitized_replay.cmake). A new target: its fuzz_NAME.cpp, corpus/NAME/ and a line here.
set(GRAINSCALE_FUZZ_TARGETS
  scenario:grainscale_dem
  materials:grainscale_dem
  shape:grainscale_dem
  stl:grainscale_dem
  motion_record:grainscale_dem
  snapshot:grainscale_dem
  checkpoint:grainscale_dem
  checkpoint_state:grainscale_dem
  cg_settings:grainscale_coarsegrain
  continuum_settings:grainscale_continuum
  gridded_flow:grainscale_continuum
  fit_data:grainscale_studies
  fit_settings:grainscale_studies
  aor_study:grainscale_studies
)
