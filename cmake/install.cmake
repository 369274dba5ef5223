# Install rules for a host engine: included by the top-level CMakeLists.txt when ML_INSTALL is on.
#
#   include/manylights/manylights.h             #include <manylights/manylights.h>: forwards to
#   include/manylights/engine/manylights.h      the public header: API types only, and the headers it
#   include/manylights/io/result.h, gpu/device_types.h, engine/pass_times.h   includes
#   include/manylights/shadows/static/static_types.h, shadows/virtual/vsm_settings.h
#   include/manylights/engine/manylights_diagnostics.h   read-backs for tools and checks
#   include/manylights/gpu/vk_check.h        ML_VK_CHECK
#   include/manylights/shadows/static/*.h       the static shadow library (encoders, bake files), for hosts
#   include/manylights/shaders/shared/*.h       that make or read bakes, and what it includes
#   include/manylights/io/*.h
#   lib/libmanylights_module.a, libmanylights_static.a, libmanylights_io.a
#   lib/cmake/manylights/manylights-config.cmake (+ version, targets): imported target manylights::manylights
#                                               (manylights::module: the same, an alias)
#   include/manylights/manylights.glsl          #include "manylights/manylights.glsl" (glslangValidator
#   include/manylights/lights/manylights_lights.glsl  -I<prefix>/include): the module's lights and shadows
#   include/manylights/shaders/{shared,static}/*.glsl, in a host's shaders (engine/manylights.h,
#   include/manylights/shadows/virtual/vsm_{types,math}.h, vsm_common.glsl   HostShaderBindings)
# Installed C++ headers include each other as <manylights/...>; a host's include path gets include/ only.
# Files GLSL reads (shaders/, the include and what it includes) use "manylights/..." instead: glslang
# resolves quoted includes through -I but has no <...> search, and C++ finds the quoted form the same way.
#   lib/pkgconfig/manylights.pc
#
# The engine's internals (device.h, program.h, resources.h, profiler.h, gbuffer.h, module_impl.h, lights/,
# culling/, shadows/gpu/, shadows/virtual/ but its settings) are not installed: the ExampleHost_install test
# checks that they are absent and that every installed engine/ header compiles on its own.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(ML_INSTALL_INCLUDE ${CMAKE_INSTALL_INCLUDEDIR}/manylights)
set(ML_INSTALL_CMAKE ${CMAKE_INSTALL_LIBDIR}/cmake/manylights)

set(ML_PUBLIC_HEADERS engine/manylights.h engine/manylights_diagnostics.h io/result.h gpu/device_types.h
    engine/pass_times.h gpu/vk_check.h lights/light_types.h shadows/virtual/vsm_settings.h)
# The libraries of their own that are installed beside the module: whole folders, so a header they start
# to include is not forgotten.
file(GLOB ML_LIBRARY_HEADERS RELATIVE ${PROJECT_SOURCE_DIR} CONFIGURE_DEPENDS
  ${PROJECT_SOURCE_DIR}/shadows/static/*.h ${PROJECT_SOURCE_DIR}/shaders/shared/*.h ${PROJECT_SOURCE_DIR}/io/*.h)
list(APPEND ML_PUBLIC_HEADERS ${ML_LIBRARY_HEADERS})
# The host-shader include and every file it includes (the VSM types and lookup are installed for GLSL:
# a C++ host has no use for them, and none of the VSM's C++ classes is installed).
file(GLOB ML_GLSL_FILES RELATIVE ${PROJECT_SOURCE_DIR} CONFIGURE_DEPENDS
  ${PROJECT_SOURCE_DIR}/shaders/shared/*.glsl ${PROJECT_SOURCE_DIR}/shaders/static/*.glsl)
list(APPEND ML_GLSL_FILES lights/manylights_lights.glsl shadows/virtual/vsm_types.h shadows/virtual/vsm_math.h
     shadows/virtual/vsm_common.glsl)
list(APPEND ML_PUBLIC_HEADERS ${ML_GLSL_FILES})
# Installed copies with their quoted includes of the module's folders rewritten to <manylights/...>:
# a host has only include/ on its path, so the module's engine/, io/, shaders/ never shadow (or are
# shadowed by) folders of the host's own. Regenerated whenever a header changes (configure dependency).
set(ML_STAGED_INCLUDE ${PROJECT_BINARY_DIR}/installed_include/manylights)
foreach(header ${ML_PUBLIC_HEADERS})
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/${header})
  file(READ ${PROJECT_SOURCE_DIR}/${header} text)
  if(header MATCHES "^shaders/" OR header IN_LIST ML_GLSL_FILES)
    string(REGEX REPLACE "#include \"((engine|gpu|io|lights|shaders|shadows|culling)/[^\"]+)\""
                         "#include \"manylights/\\1\"" text "${text}")
  else()
    string(REGEX REPLACE "#include \"((engine|gpu|io|lights|shaders|shadows|culling)/[^\"]+)\""
                         "#include <manylights/\\1>" text "${text}")
  endif()
  file(CONFIGURE OUTPUT ${ML_STAGED_INCLUDE}/${header} CONTENT "${text}" @ONLY)
  get_filename_component(dir ${header} DIRECTORY)
  install(FILES ${ML_STAGED_INCLUDE}/${header} DESTINATION ${ML_INSTALL_INCLUDE}/${dir} COMPONENT manylights)
endforeach()
file(CONFIGURE OUTPUT ${ML_STAGED_INCLUDE}/manylights.h CONTENT
     "// The host's entry point: #include <manylights/manylights.h> (include/ on the path, nothing else).\n#pragma once\n#include <manylights/engine/manylights.h>\n")
# The folder a host's glslangValidator gets as -I for "manylights/manylights.glsl": with add_subdirectory
# the staged tree (the same files as installed), after find_package <prefix>/include (the config file).
set(MANYLIGHTS_GLSL_INCLUDE_DIR ${PROJECT_BINARY_DIR}/installed_include CACHE INTERNAL
    "glslangValidator -I folder of manylights/manylights.glsl (the host-shader include)")
file(CONFIGURE OUTPUT ${ML_STAGED_INCLUDE}/manylights.glsl CONTENT
     "// A host shader's entry point: #include \"manylights/manylights.glsl\" (glslangValidator -I<prefix>/include).\n#include \"manylights/lights/manylights_lights.glsl\"\n")
install(FILES ${ML_STAGED_INCLUDE}/manylights.h ${ML_STAGED_INCLUDE}/manylights.glsl DESTINATION ${ML_INSTALL_INCLUDE}
        COMPONENT manylights)

install(TARGETS manylights_module manylights_static manylights_io EXPORT manylightsTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT manylights)
install(EXPORT manylightsTargets NAMESPACE manylights:: DESTINATION ${ML_INSTALL_CMAKE} COMPONENT manylights)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/manylights-config.cmake.in
                              ${PROJECT_BINARY_DIR}/manylights-config.cmake INSTALL_DESTINATION ${ML_INSTALL_CMAKE}
                              PATH_VARS CMAKE_INSTALL_INCLUDEDIR)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/manylights-config-version.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/manylights-config.cmake ${PROJECT_BINARY_DIR}/manylights-config-version.cmake
        DESTINATION ${ML_INSTALL_CMAKE} COMPONENT manylights)

# pkg-config: relocatable (prefix from the .pc file's own folder), so `cmake --install --prefix P` works.
file(RELATIVE_PATH ML_PC_TO_PREFIX /root/${CMAKE_INSTALL_LIBDIR}/pkgconfig /root)
string(REGEX REPLACE "/$" "" ML_PC_TO_PREFIX "${ML_PC_TO_PREFIX}")
configure_file(${PROJECT_SOURCE_DIR}/cmake/manylights.pc.in ${PROJECT_BINARY_DIR}/manylights.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/manylights.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig COMPONENT manylights)
