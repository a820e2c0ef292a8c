# brdfbake_add_library(<part> SOURCES ... PUBLIC_DEPS ... PRIVATE_DEPS ...): the library brdfbake_<part>
# (static, or shared with BUILD_SHARED_LIBS), exported as brdfbake::<part> in its own export set
# brdfbake_<part>Targets, so that find_package(brdfbake COMPONENTS <part>) loads only the parts a
# renderer asks for. Public headers live under include/brdfbake/<part>/ and install with the part.
function(brdfbake_add_library part)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(brdfbake_${part} ${ARG_SOURCES})
  add_library(brdfbake::${part} ALIAS brdfbake_${part})
  set_target_properties(brdfbake_${part} PROPERTIES EXPORT_NAME ${part} OUTPUT_NAME brdfbake_${part}
                        VERSION ${PROJECT_VERSION} SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR})
  target_include_directories(brdfbake_${part} PUBLIC
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>
    $<BUILD_INTERFACE:${PROJECT_BINARY_DIR}/generated>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(brdfbake_${part} PUBLIC ${ARG_PUBLIC_DEPS}
                        PRIVATE ${ARG_PRIVATE_DEPS} $<BUILD_INTERFACE:brdfbake_warnings>)
  target_compile_features(brdfbake_${part} PUBLIC cxx_std_20)
  # Library code never reads errno: let sqrt and friends compile to single instructions. Nor does it
  # read floating-point exception flags: let loops with comparisons and selects vectorise (the
  # baker's fast paths); values are unchanged (no reassociation).
  if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
    target_compile_options(brdfbake_${part} PRIVATE -fno-math-errno -fno-trapping-math)
  endif()
  install(TARGETS brdfbake_${part} EXPORT brdfbake_${part}Targets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
          LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
          RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  install(EXPORT brdfbake_${part}Targets NAMESPACE brdfbake::
          DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/brdfbake)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/brdfbake/${part} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/brdfbake)
endfunction()
