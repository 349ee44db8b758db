# cmake --install: the CLI (top-level CMakeLists.txt), the public headers,
# the libraries and the CMake package `massid` (massid::core,
# massid::emulator, massid::c), and pkg-config files. The MuJoCo plants
# (massid_emulator_mujoco) are the CLI's simulation and are not installed, so
# a user of the predictor or the controller never needs MuJoCo.
include(CMakePackageConfigHelpers)
set(MASSID_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/massid)

# Without MASSID_EMULATOR (the library alone, as on aarch64) the package has
# massid::core and massid::c only.
set(MASSID_INSTALLED_LIBRARIES massid_core)
foreach(part IN LISTS MASSID_PARTS)
  list(APPEND MASSID_INSTALLED_LIBRARIES massid_part_${part})
endforeach()
if(TARGET massid_emulator)
  list(APPEND MASSID_INSTALLED_LIBRARIES massid_emulator)
endif()
install(TARGETS ${MASSID_INSTALLED_LIBRARIES} EXPORT massidTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/massid DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        FILES_MATCHING PATTERN "*.hpp")
install(FILES ${PROJECT_BINARY_DIR}/include/massid/version.hpp
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/massid)
if(TARGET massid_emulator)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/emulator/include/massid/emulator
          DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/massid
          FILES_MATCHING PATTERN "*.hpp"
          PATTERN "mujoco_plant.hpp" EXCLUDE PATTERN "emulation.hpp" EXCLUDE)
endif()

install(EXPORT massidTargets NAMESPACE massid:: DESTINATION ${MASSID_CMAKE_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/massidConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/massidConfig.cmake
                              INSTALL_DESTINATION ${MASSID_CMAKE_DIR})
# 0.x: a minor version may change the interface.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/massidConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/massidConfig.cmake ${PROJECT_BINARY_DIR}/massidConfigVersion.cmake
        DESTINATION ${MASSID_CMAKE_DIR})

# Relocatable: the prefix is found from the .pc file's own directory, so a
# DESTDIR-staged or moved installation works.
file(RELATIVE_PATH MASSID_PC_UP /${CMAKE_INSTALL_LIBDIR}/pkgconfig /)
set(MASSID_PC_PREFIX "\${pcfiledir}/${MASSID_PC_UP}")
string(REGEX REPLACE "/$" "" MASSID_PC_PREFIX "${MASSID_PC_PREFIX}")
configure_file(${PROJECT_SOURCE_DIR}/cmake/massid.pc.in ${PROJECT_BINARY_DIR}/massid.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/massid.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
if(TARGET massid_c)
  configure_file(${PROJECT_SOURCE_DIR}/cmake/massid-c.pc.in ${PROJECT_BINARY_DIR}/massid-c.pc @ONLY)
  install(FILES ${PROJECT_BINARY_DIR}/massid-c.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
endif()
