# Install rules for a host engine: included by the top-level CMakeLists.txt when ML_INSTALL is on.
#
#   include/manylights/engine/manylights.h     the public header, and every header it includes
#   include/manylights/shadows/static/*.h      (the public header includes static_method.h today)
#   include/manylights/shaders/shared/*.h      GPU structs and light math shared with the shaders
#   include/manylights/shadows/virtual/*.h    (virtual shadow map settings and stats, vsm_settings.h)
#   lib/libmanylights_module.a, libmanylights_static.a, libmanylights_io.a
#   lib/cmake/manylights/manylights-config.cmake (+ version, targets): imported target manylights::module
#   lib/pkgconfig/manylights.pc
#
# Whole folders are installed rather than a hand-kept list, so a header the public header starts to
# include is not forgotten; the ExampleHostInstalled test compiles a host against the installed tree.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(ML_INSTALL_INCLUDE ${CMAKE_INSTALL_INCLUDEDIR}/manylights)
set(ML_INSTALL_CMAKE ${CMAKE_INSTALL_LIBDIR}/cmake/manylights)

# module_impl.h is the tests' view of the internals (it includes build-generated SPIR-V): not installed.
file(GLOB ML_PUBLIC_HEADERS RELATIVE ${PROJECT_SOURCE_DIR} CONFIGURE_DEPENDS
  ${PROJECT_SOURCE_DIR}/engine/*.h ${PROJECT_SOURCE_DIR}/shadows/static/*.h ${PROJECT_SOURCE_DIR}/shaders/shared/*.h
  ${PROJECT_SOURCE_DIR}/shadows/virtual/*.h ${PROJECT_SOURCE_DIR}/io/*.h)
list(REMOVE_ITEM ML_PUBLIC_HEADERS engine/module_impl.h)
foreach(header ${ML_PUBLIC_HEADERS})
  get_filename_component(dir ${header} DIRECTORY)
  install(FILES ${PROJECT_SOURCE_DIR}/${header} DESTINATION ${ML_INSTALL_INCLUDE}/${dir} COMPONENT manylights)
endforeach()

install(TARGETS manylights_module manylights_static manylights_io EXPORT manylightsTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT manylights)
install(EXPORT manylightsTargets NAMESPACE manylights:: DESTINATION ${ML_INSTALL_CMAKE} COMPONENT manylights)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/manylights-config.cmake.in
                              ${PROJECT_BINARY_DIR}/manylights-config.cmake INSTALL_DESTINATION ${ML_INSTALL_CMAKE})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/manylights-config-version.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/manylights-config.cmake ${PROJECT_BINARY_DIR}/manylights-config-version.cmake
        DESTINATION ${ML_INSTALL_CMAKE} COMPONENT manylights)

# pkg-config: relocatable (prefix from the .pc file's own folder), so `cmake --install --prefix P` works.
file(RELATIVE_PATH ML_PC_TO_PREFIX /root/${CMAKE_INSTALL_LIBDIR}/pkgconfig /root)
string(REGEX REPLACE "/$" "" ML_PC_TO_PREFIX "${ML_PC_TO_PREFIX}")
string(REPLACE ";" " -D" ML_PC_DEFS "-D${ML_DEFS}")
configure_file(${PROJECT_SOURCE_DIR}/cmake/manylights.pc.in ${PROJECT_BINARY_DIR}/manylights.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/manylights.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig COMPONENT manylights)
