# Install rules for a host engine: included by the top-level CMakeLists.txt when ML_INSTALL is on.
#
#   include/manylights/*.h                      the public API: a copy of the source tree's include/manylights/
#                                               (manylights.h the entry point; its header comment lists them)
#   include/manylights/manylights.glsl          #include "manylights/manylights.glsl" (glslangValidator
#                                               -I<prefix>/include): the module's lights and shadows in a
#                                               host's shaders, one self-contained file (below)
#   lib/libmanylights_module.a, libmanylights_static.a, libmanylights_io.a
#   lib/cmake/manylights/manylights-config.cmake (+ version, targets): imported target manylights::manylights
#                                               (manylights::module: the same, an alias)
#   lib/pkgconfig/manylights.pc
# Nothing of the module's internal folders is installed (engine/, gpu/, io/, shaders/, shadows/, lights/):
# the public headers include only each other, which the layer check keeps so (include/ is its lowest
# layer), and ExampleHost_install checks that every installed header compiles on its own.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(ML_INSTALL_INCLUDE ${CMAKE_INSTALL_INCLUDEDIR}/manylights)
set(ML_INSTALL_CMAKE ${CMAKE_INSTALL_LIBDIR}/cmake/manylights)

# The staged tree <build>/installed_include/manylights: the files as installed, for hosts built with
# add_subdirectory (their glslangValidator -I) and the tests that compile against the install layout.
set(ML_STAGED_INCLUDE ${PROJECT_BINARY_DIR}/installed_include/manylights)
file(REMOVE_RECURSE ${ML_STAGED_INCLUDE})
file(GLOB ML_PUBLIC_HEADERS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/include/manylights/*.h)
foreach(header ${ML_PUBLIC_HEADERS})
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${header})
  file(COPY ${header} DESTINATION ${ML_STAGED_INCLUDE})
endforeach()
install(FILES ${ML_PUBLIC_HEADERS} DESTINATION ${ML_INSTALL_INCLUDE} COMPONENT manylights)

# manylights.glsl: lights/manylights_lights.glsl with every quoted include inlined where it first appears
# (each file once, as its include guard would have it) and the module's own comments removed (they speak
# of its internal files; the header written below and docs/integration.md document the include), so the
# install needs none of the module's shader folders and a host's -I<prefix>/include resolves it alone. A quoted include is looked up beside its
# file, then at the source root, include/ and shaders/ (the module's own glslangValidator -I order).
set_property(GLOBAL PROPERTY ML_GLSL_SEEN "")
function(ml_inline_glsl path out)
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${path})
  file(READ ${path} text)
  get_filename_component(dir ${path} DIRECTORY)
  set(result "")
  while(TRUE)
    string(REGEX MATCH "(^|\n)[ \t]*#[ \t]*include[ \t]*\"([^\"]+)\"[^\n]*" line "${text}")
    if(NOT line)
      break()
    endif()
    set(name ${CMAKE_MATCH_2})
    string(FIND "${text}" "${line}" pos)
    string(LENGTH "${line}" length)
    string(SUBSTRING "${text}" 0 ${pos} before)
    math(EXPR rest "${pos} + ${length}")
    string(SUBSTRING "${text}" ${rest} -1 text)
    string(APPEND result "${before}\n")
    set(found "")
    foreach(base ${dir} ${PROJECT_SOURCE_DIR} ${PROJECT_SOURCE_DIR}/include ${PROJECT_SOURCE_DIR}/shaders)
      if(EXISTS ${base}/${name})
        get_filename_component(found ${base}/${name} ABSOLUTE)
        break()
      endif()
    endforeach()
    if(NOT found)
      message(FATAL_ERROR "manylights.glsl: ${path} includes \"${name}\", found nowhere")
    endif()
    get_property(seen GLOBAL PROPERTY ML_GLSL_SEEN)
    if(found IN_LIST seen)
      string(APPEND result "// (${name}: inlined above)")
    else()
      set_property(GLOBAL APPEND PROPERTY ML_GLSL_SEEN ${found})
      ml_inline_glsl(${found} inner)
      string(APPEND result "// ---- ${name}\n${inner}// ---- end of ${name}")
    endif()
  endwhile()
  string(APPEND result "${text}")
  set(${out} "${result}" PARENT_SCOPE)
endfunction()
ml_inline_glsl(${PROJECT_SOURCE_DIR}/lights/manylights_lights.glsl ML_GLSL_TEXT)
string(REGEX REPLACE "//[^\n]*" "" ML_GLSL_TEXT "${ML_GLSL_TEXT}")
string(REGEX REPLACE "[ \t]+\n" "\n" ML_GLSL_TEXT "${ML_GLSL_TEXT}")
string(REGEX REPLACE "\n\n\n+" "\n\n" ML_GLSL_TEXT "${ML_GLSL_TEXT}")
file(READ ${PROJECT_SOURCE_DIR}/cmake/manylights_glsl_header.txt ML_GLSL_HEADER)
file(WRITE ${ML_STAGED_INCLUDE}/manylights.glsl "${ML_GLSL_HEADER}${ML_GLSL_TEXT}")
# The folder a host's glslangValidator gets as -I for "manylights/manylights.glsl": with add_subdirectory
# the staged tree, after find_package <prefix>/include (the config file).
set(MANYLIGHTS_GLSL_INCLUDE_DIR ${PROJECT_BINARY_DIR}/installed_include CACHE INTERNAL
    "glslangValidator -I folder of manylights/manylights.glsl (the host-shader include)")
install(FILES ${ML_STAGED_INCLUDE}/manylights.glsl DESTINATION ${ML_INSTALL_INCLUDE} COMPONENT manylights)

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
