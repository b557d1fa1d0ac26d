# Debian's libosd-dev ships a CMake config that points at libosdCPU.a, which the package does not
# contain. Build our own imported target from the header and the shared library.
# OpenSubdiv is a reference for tests and benchmarks only; the service never links it.
find_path(OSD_INCLUDE_DIR opensubdiv/version.h REQUIRED)
find_library(OSD_CPU_LIBRARY osdCPU REQUIRED)
if(NOT TARGET OpenSubdiv::osdCPU)
  add_library(OpenSubdiv::osdCPU UNKNOWN IMPORTED)
  set_target_properties(OpenSubdiv::osdCPU PROPERTIES
    IMPORTED_LOCATION "${OSD_CPU_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${OSD_INCLUDE_DIR}")
endif()
