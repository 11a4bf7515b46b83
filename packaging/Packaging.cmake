# Installation (`cmake --install build --prefix DIR`) and the Debian package (`cpack -G DEB`
# in build/): docs/install.md. Included from the top-level CMakeLists.txt once every target
# exists. Nothing installed refers to the source or build tree: the executable finds its
# libraries relative to itself and its config at run time (docs/config.md).
include(GNUInstallDirs)

set(VSCULPT_PRIVATE_LIBDIR "${CMAKE_INSTALL_LIBDIR}/vsculpt")
set(VSCULPT_UDEV_RULES_DIR "lib/udev/rules.d" CACHE STRING
    "Where the udev rule is installed, relative to the prefix (udev reads /usr/lib/udev/rules.d \
and /etc/udev/rules.d, not /usr/local)")

# --- The executable and vsculpt's own libraries --------------------------------------------
# Our libraries are shared whenever BUILD_SHARED_LIBS is on, and Debian's FindOpenVDB.cmake
# turns it on in our scope. Shared ones are installed to a private folder (not a public
# library: no stable ABI, no SONAME version) that the RUNPATHs name relative to each file
# ($ORIGIN); static ones are inside the executable already. The build tree keeps its own
# RUNPATH; `cmake --install` rewrites it.
install(TARGETS vsculpt RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
file(RELATIVE_PATH vsculpt_bin_to_lib "/${CMAKE_INSTALL_BINDIR}" "/${VSCULPT_PRIVATE_LIBDIR}")
set_target_properties(vsculpt PROPERTIES INSTALL_RPATH "$ORIGIN/${vsculpt_bin_to_lib}")
foreach(lib vsculpt_app vsculpt_studio vsculpt_core vsculpt_sketch vsculpt_render
            vsculpt_devices)
  get_target_property(type ${lib} TYPE)
  if(type STREQUAL "SHARED_LIBRARY")
    set_target_properties(${lib} PROPERTIES INSTALL_RPATH "$ORIGIN")
    install(TARGETS ${lib} LIBRARY DESTINATION ${VSCULPT_PRIVATE_LIBDIR})
  endif()
endforeach()

# --- Data, config template, udev rule, documentation -----------------------------------------
# The shipped config is a template (every key, its default, a comment): vsculpt needs no
# file, and reads ~/.config/vsculpt/sculpt.json or $VSCULPT_CONFIG when there is one.
install(FILES ${PROJECT_SOURCE_DIR}/configs/sculpt.json
        DESTINATION ${CMAKE_INSTALL_DATADIR}/vsculpt)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/examples/
        DESTINATION ${CMAKE_INSTALL_DATADIR}/vsculpt/examples)
install(FILES ${PROJECT_SOURCE_DIR}/configs/70-vsculpt.rules DESTINATION ${VSCULPT_UDEV_RULES_DIR})
# docs/ keeps its folder so the "docs/x.md" references in README.md and the docs resolve.
install(FILES ${PROJECT_SOURCE_DIR}/README.md ${PROJECT_SOURCE_DIR}/LICENSE
        DESTINATION ${CMAKE_INSTALL_DOCDIR})
# Debian Policy 12.5: the licence as /usr/share/doc/PACKAGE/copyright.
install(FILES ${PROJECT_SOURCE_DIR}/LICENSE DESTINATION ${CMAKE_INSTALL_DOCDIR} RENAME copyright)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR}/docs
        FILES_MATCHING PATTERN "*.md")

# --- Desktop integration -------------------------------------------------------------------
install(FILES ${CMAKE_CURRENT_LIST_DIR}/vsculpt.bash-completion
        DESTINATION ${CMAKE_INSTALL_DATADIR}/bash-completion/completions RENAME vsculpt)
install(FILES ${CMAKE_CURRENT_LIST_DIR}/vsculpt.desktop
        DESTINATION ${CMAKE_INSTALL_DATADIR}/applications)
install(FILES ${CMAKE_CURRENT_LIST_DIR}/vsculpt.svg
        DESTINATION ${CMAKE_INSTALL_DATADIR}/icons/hicolor/scalable/apps)

# --- The man page, generated from the built executable's --help ------------------------------
# help2man when it is there (scripts/install-deps.sh installs it), else a plainer page from
# the same text. Not in sanitizer builds (never installed; no need to run them at build time).
if(NOT VSCULPT_SANITIZE)
  find_program(HELP2MAN_EXECUTABLE help2man)
  if(NOT HELP2MAN_EXECUTABLE)
    message(STATUS "help2man not found: vsculpt.1 is written without it (plainer)")
  endif()
  set(vsculpt_man_dir ${CMAKE_BINARY_DIR}/packaging)
  add_custom_command(
    OUTPUT ${vsculpt_man_dir}/vsculpt.1 ${vsculpt_man_dir}/vsculpt.1.gz
    COMMAND ${CMAKE_COMMAND} -E make_directory ${vsculpt_man_dir}
    COMMAND ${CMAKE_COMMAND} "-DVSCULPT=$<TARGET_FILE:vsculpt>"
            "-DHELP2MAN=${HELP2MAN_EXECUTABLE}" "-DEXTRA=${CMAKE_CURRENT_LIST_DIR}/vsculpt.h2m"
            "-DOUT=${vsculpt_man_dir}/vsculpt.1" -P ${CMAKE_CURRENT_LIST_DIR}/make-man.cmake
    # Debian wants man pages compressed; -n: no name or time stamp, the same bytes every build.
    COMMAND gzip -9 -n -f -k ${vsculpt_man_dir}/vsculpt.1
    DEPENDS vsculpt vsculpt_app ${CMAKE_CURRENT_LIST_DIR}/make-man.cmake ${CMAKE_CURRENT_LIST_DIR}/vsculpt.h2m
    COMMENT "Writing the man page vsculpt.1 from vsculpt --help"
    VERBATIM)
  add_custom_target(vsculpt_man ALL DEPENDS ${vsculpt_man_dir}/vsculpt.1.gz)
  install(FILES ${vsculpt_man_dir}/vsculpt.1.gz DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
endif()

# --- The Debian package: cpack -G DEB (in the build folder) ----------------------------------
set(VSCULPT_PACKAGE_MAINTAINER "vsculpt developers <vsculpt-developers@invalid>" CACHE STRING
    "The Debian package's Maintainer field, \"Name <email>\"")
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME vsculpt)
set(CPACK_PACKAGE_VENDOR "vsculpt developers")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT "${VSCULPT_PACKAGE_MAINTAINER}")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "immersive virtual-sculpting modeler")
# Lines as the control file shows them (Debian wants them under 80 columns).
string(JOIN "\n" CPACK_PACKAGE_DESCRIPTION
  "Clay added and carved with a pen-type tool, held with a 3D mouse, zoomed"
  "into for detail finer than the tool you started with, with a tablet sketch"
  "mode feeding the same surface: implicit surfaces on locally refined skeleton"
  "lattices, an incremental polygonizer, undo without limit, crash-safe projects."
  "Reads Polhemus trackers, 3Dconnexion 3D mice, pen tablets and Rift headset"
  "IMUs (udev rule included); plays scripts headless and exports OBJ, STL, PLY,"
  "glTF, DXF and OpenVDB.")
set(CPACK_RESOURCE_FILE_LICENSE ${PROJECT_SOURCE_DIR}/LICENSE)
set(CPACK_RESOURCE_FILE_README ${PROJECT_SOURCE_DIR}/README.md)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${VSCULPT_PACKAGE_MAINTAINER}")
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
# udev reads the new rule and applies it to the devices already plugged in, so they work
# without a replug (found by QA: the package installed the rule and left it unread).
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA ${PROJECT_SOURCE_DIR}/packaging/postinst)
find_program(VSCULPT_DPKG_SHLIBDEPS dpkg-shlibdeps)
if(VSCULPT_DPKG_SHLIBDEPS)
  # Depends: from the libraries the binaries really link (OpenVDB, TBB, Embree, GLFW, ...).
  set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
else()
  message(STATUS "dpkg-shlibdeps not found (package dpkg-dev): a .deb would list no Depends")
endif()
# `make package_source` / cpack --config CPackSourceConfig.cmake: sources only.
set(CPACK_SOURCE_GENERATOR TGZ)
set(CPACK_SOURCE_IGNORE_FILES "/\\.git/" "/build[^/]*/" "/\\.cache/")
include(CPack)
