# `cmake --install`: the nhc command and the program it starts, the public headers (docs/library.md) and
# the libraries base, codegen, runtime, tools, jit, app, linearize, connect (and, when HDF5 was found,
# ensemble), the exported targets nhc::nhc, nhc::base, nhc::codegen,
# nhc::runtime, nhc::tools, nhc::jit, nhc::app, nhc::linearize, nhc::connect, nhc::ensemble, and a package config with version file
# and nhc_add_model(), so that find_package(nhc) works (examples/app/).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(NHC_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/nhc" CACHE STRING
    "Where the nhc package config is installed, relative to the prefix")

set_target_properties(nhc_base PROPERTIES EXPORT_NAME base)
set_target_properties(nhc_codegen PROPERTIES EXPORT_NAME codegen)
set_target_properties(nhc_runtime PROPERTIES EXPORT_NAME runtime)
set_target_properties(nhc_tools PROPERTIES EXPORT_NAME tools)
set_target_properties(nhc_jit PROPERTIES EXPORT_NAME jit)
set_target_properties(nhc_linearize PROPERTIES EXPORT_NAME linearize)
set_target_properties(nhc_connect PROPERTIES EXPORT_NAME connect)
set_target_properties(nhc_app PROPERTIES EXPORT_NAME app)
set(nhc_installed_libraries nhc_base nhc_codegen nhc_runtime nhc_tools nhc_jit nhc_app nhc_linearize nhc_connect)
# nhcConfig.cmake looks for the ensemble's dependencies only when the ensemble was installed.
set(NHC_PACKAGE_HAS_ENSEMBLE OFF)
set(NHC_PACKAGE_ENSEMBLE_USES_MPI OFF)
if(TARGET nhc_ensemble)
  set_target_properties(nhc_ensemble PROPERTIES EXPORT_NAME ensemble)
  list(APPEND nhc_installed_libraries nhc_ensemble)
  set(NHC_PACKAGE_HAS_ENSEMBLE ON)
  if(MPI_C_FOUND)
    set(NHC_PACKAGE_ENSEMBLE_USES_MPI ON)
  endif()
endif()
set_target_properties(nhc PROPERTIES EXPORT_NAME nhc)
if(BUILD_SHARED_LIBS)
  set_target_properties(nhc_main nhc_ensemble_program nhc_optimize_program PROPERTIES INSTALL_RPATH "$ORIGIN/../../${CMAKE_INSTALL_LIBDIR}")
endif()
# The command bin/nhc starts the program libexec/nhc/nhc-main, or nhc-ensemble or nhc-optimize
# beside it for their commands (cli/launcher.cpp, cli/command_programs.hpp).
install(TARGETS nhc_main nhc_ensemble_program nhc_optimize_program RUNTIME DESTINATION ${CMAKE_INSTALL_LIBEXECDIR}/nhc)

install(TARGETS nhc ${nhc_installed_libraries}
  EXPORT nhcTargets
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
# The public headers only (cmake/nhcPublicHeaders.cmake, docs/library.md): ROOM/nhc/X goes to
# include/nhc/X, so that the rooms share the top directory nhc/.
include(${PROJECT_SOURCE_DIR}/cmake/nhcPublicHeaders.cmake)
nhc_public_headers(nhc_public_headers)
foreach(header IN LISTS nhc_public_headers)
  string(FIND "${header}" "/" room_end)  # ROOM/ (REGEX REPLACE "^…" would strip every directory)
  math(EXPR room_end "${room_end} + 1")
  string(SUBSTRING "${header}" ${room_end} -1 installed)
  get_filename_component(installed_dir "${installed}" DIRECTORY)
  install(FILES ${PROJECT_SOURCE_DIR}/${header} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/${installed_dir})
endforeach()

install(EXPORT nhcTargets NAMESPACE nhc:: DESTINATION ${NHC_INSTALL_CMAKEDIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/nhcConfig.cmake.in
  ${PROJECT_BINARY_DIR}/nhcConfig.cmake
  INSTALL_DESTINATION ${NHC_INSTALL_CMAKEDIR})
# 0.x: a minor version may change the generated-code contract.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/nhcConfigVersion.cmake
  VERSION ${PROJECT_VERSION}
  COMPATIBILITY SameMinorVersion)
install(FILES
  ${PROJECT_BINARY_DIR}/nhcConfig.cmake
  ${PROJECT_BINARY_DIR}/nhcConfigVersion.cmake
  ${PROJECT_SOURCE_DIR}/cmake/nhcFunctions.cmake
  DESTINATION ${NHC_INSTALL_CMAKEDIR})

# `cpack -G DEB` in the build tree: a Debian package of everything above, installed under /usr
# (the Python package in /usr/lib/python3.X/dist-packages). Depends: the libraries' own (dpkg-shlibdeps)
# and what nhc needs at run time beyond them — a C++ compiler and the headers the generated code and
# the installed nhc headers include (nhc simulate compiles models; find_package(nhc) users compile
# against nhc::codegen and nhc::runtime), and Python's numpy for the module. Checked by install:deb.
set(CPACK_PACKAGE_NAME nhc)
set(CPACK_PACKAGE_VENDOR "nhc")
set(CPACK_PACKAGE_CONTACT "nhc maintainers <nhc@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "the nonholonomic compiler: equations of motion with nonholonomic constraints, derived, analysed, generated as C++ and integrated")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# The -dev packages are what nhcConfig.cmake's find_dependency() calls look for (pkg-config for GiNaC;
# HDF5 and MPI, and a C compiler to probe them, when the ensemble is in the package).
set(nhc_deb_depends "g++, cmake, pkg-config, libginac-dev, libcln-dev, libeigen3-dev, libsundials-dev, libsuitesparse-dev, libfmt-dev, libtomlplusplus-dev, libssl-dev, python3, python3-numpy")
if(NHC_PACKAGE_HAS_ENSEMBLE)
  string(APPEND nhc_deb_depends ", gcc, libhdf5-dev")
  if(NHC_PACKAGE_ENSEMBLE_USES_MPI)
    string(APPEND nhc_deb_depends ", libopenmpi-dev, openmpi-bin")
  endif()
endif()
set(CPACK_DEBIAN_PACKAGE_DEPENDS "${nhc_deb_depends}")
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "gnuplot-nox, libjs-three, texlive-latex-base, python3-matplotlib")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "chromium")
include(CPack)
