# Imported targets for the libraries whose Debian 12 CMake configs cannot be used on a machine
# that has only the -dev packages:
#   - OpenImageIO's config exports targets for its command-line tools (/usr/bin/iconvert, ...),
#     which only the openimageio-tools package installs, and names OpenCV's include folder;
#   - Imath's config (pulled in by OpenImageIO's) names a Python library;
#   - libmatio ships no CMake config at all.
# So the headers and libraries are found directly. The targets are created again by every project
# that includes this file (brdfbake itself and, through brdfbakeConfig.cmake, its consumers), so the
# installed package names no absolute library path and stays relocatable.
#
#   brdfbake_find_openimageio()  ->  brdfbake_deps::OpenImageIO   (OpenImageIO + Imath)
#   brdfbake_find_matio()        ->  brdfbake_deps::matio

# A missing library stops brdfbake's own configure (FATAL_ERROR); in a consumer's find_package
# (BRDFBAKE_DEPENDENCIES_SOFT set by brdfbakeConfig.cmake) it is recorded in
# BRDFBAKE_DEPENDENCY_MISSING instead, so the package can report itself not found.
macro(_brdfbake_require var what package)
  if(NOT ${var})
    set(_brdfbake_missing "${what} not found (Debian: apt-get install ${package}); set ${var} to its location")
    if(BRDFBAKE_DEPENDENCIES_SOFT)
      set(BRDFBAKE_DEPENDENCY_MISSING "${_brdfbake_missing}" PARENT_SCOPE)
      return()
    endif()
    message(FATAL_ERROR "brdfbake: ${_brdfbake_missing}")
  endif()
endmacro()

function(brdfbake_find_openimageio)
  if(TARGET brdfbake_deps::OpenImageIO)
    return()
  endif()
  find_path(BRDFBAKE_OIIO_INCLUDE_DIR OpenImageIO/imageio.h)
  find_library(BRDFBAKE_OIIO_LIBRARY NAMES OpenImageIO)
  find_library(BRDFBAKE_OIIO_UTIL_LIBRARY NAMES OpenImageIO_Util)
  find_path(BRDFBAKE_IMATH_INCLUDE_DIR Imath/half.h)
  find_library(BRDFBAKE_IMATH_LIBRARY NAMES Imath-3_1 Imath)
  _brdfbake_require(BRDFBAKE_OIIO_INCLUDE_DIR "OpenImageIO headers" libopenimageio-dev)
  _brdfbake_require(BRDFBAKE_OIIO_LIBRARY "libOpenImageIO" libopenimageio-dev)
  _brdfbake_require(BRDFBAKE_OIIO_UTIL_LIBRARY "libOpenImageIO_Util" libopenimageio-dev)
  _brdfbake_require(BRDFBAKE_IMATH_INCLUDE_DIR "Imath headers" libimath-dev)
  _brdfbake_require(BRDFBAKE_IMATH_LIBRARY "libImath" libimath-dev)
  add_library(brdfbake_deps::OpenImageIO INTERFACE IMPORTED GLOBAL)
  set_target_properties(brdfbake_deps::OpenImageIO PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${BRDFBAKE_OIIO_INCLUDE_DIR};${BRDFBAKE_IMATH_INCLUDE_DIR};${BRDFBAKE_IMATH_INCLUDE_DIR}/Imath"
    INTERFACE_LINK_LIBRARIES
      "${BRDFBAKE_OIIO_LIBRARY};${BRDFBAKE_OIIO_UTIL_LIBRARY};${BRDFBAKE_IMATH_LIBRARY}")
endfunction()

function(brdfbake_find_matio)
  if(TARGET brdfbake_deps::matio)
    return()
  endif()
  find_path(BRDFBAKE_MATIO_INCLUDE_DIR matio.h)
  find_library(BRDFBAKE_MATIO_LIBRARY NAMES matio)
  _brdfbake_require(BRDFBAKE_MATIO_INCLUDE_DIR "matio.h" libmatio-dev)
  _brdfbake_require(BRDFBAKE_MATIO_LIBRARY "libmatio" libmatio-dev)
  add_library(brdfbake_deps::matio INTERFACE IMPORTED GLOBAL)
  set_target_properties(brdfbake_deps::matio PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${BRDFBAKE_MATIO_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${BRDFBAKE_MATIO_LIBRARY}")
endfunction()
