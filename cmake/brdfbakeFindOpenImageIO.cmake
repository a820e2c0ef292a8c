# Finds OpenImageIO and removes the OpenCV include folder that Debian's OpenImageIO CMake config
# names (/usr/include/opencv4) although OpenCV is not a dependency of the headers we use. Without
# this, CMake refuses the imported target on machines without OpenCV ("non-existent path").
# Installed next to brdfbakeConfig.cmake so consumers get the same fix.
find_package(OpenImageIO CONFIG REQUIRED)
if(TARGET OpenImageIO::OpenImageIO)
  foreach(_prop INTERFACE_INCLUDE_DIRECTORIES INTERFACE_SYSTEM_INCLUDE_DIRECTORIES)
    get_target_property(_dirs OpenImageIO::OpenImageIO ${_prop})
    if(_dirs)
      set(_kept "")
      foreach(_d IN LISTS _dirs)
        if(EXISTS "${_d}" OR _d MATCHES "^\\$<")
          list(APPEND _kept "${_d}")
        endif()
      endforeach()
      set_target_properties(OpenImageIO::OpenImageIO PROPERTIES ${_prop} "${_kept}")
    endif()
  endforeach()
  unset(_dirs)
  unset(_kept)
endif()
