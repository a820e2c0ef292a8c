# brdfbake_add_library(<part> SOURCES ... DEPS ...): a static library brdfbake_<part>, exported as
# brdfbake::<part>, with the public headers under include/brdfbake/<part>/.
function(brdfbake_add_library part)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(brdfbake_${part} ${ARG_SOURCES})
  add_library(brdfbake::${part} ALIAS brdfbake_${part})
  set_target_properties(brdfbake_${part} PROPERTIES EXPORT_NAME ${part} OUTPUT_NAME brdfbake_${part})
  target_include_directories(brdfbake_${part} PUBLIC
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>
    $<BUILD_INTERFACE:${PROJECT_BINARY_DIR}/generated>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(brdfbake_${part} PUBLIC ${ARG_PUBLIC_DEPS}
                        PRIVATE ${ARG_PRIVATE_DEPS} $<BUILD_INTERFACE:brdfbake_warnings>)
  # Library code never reads errno: let sqrt and friends compile to single instructions.
  target_compile_options(brdfbake_${part} PRIVATE -fno-math-errno)
  install(TARGETS brdfbake_${part} EXPORT brdfbakeTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
          LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
endfunction()
