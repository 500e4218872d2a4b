# Installs canopy as a CMake package (issue 13): libraries, public headers, the CLI and its
# data, and canopyConfig.cmake so another project can write
#   find_package(canopy REQUIRED COMPONENTS mapping nbv motion)
# and link canopy::mapping, canopy::nbv, canopy::motion. The MuJoCo-free libraries form one
# export set (canopyTargets); sim, mission and experiments, which need MuJoCo and OSMesa, another
# (canopySimTargets), loaded only for those components (jobs, over them all, is one of these).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(CANOPY_CORE_MODULES common ros2 robot world perception mapping datasets evaluation nbv motion settings records)
set(CANOPY_SIM_MODULES sim video mission experiments jobs)
set(CANOPY_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/canopy)

set(canopy_core_targets canopy_ompl canopy_warnings)
set(canopy_sim_targets "")
foreach(module ${CANOPY_CORE_MODULES} ${CANOPY_SIM_MODULES})
  if(NOT TARGET canopy_${module})
    continue()
  endif()
  set_target_properties(canopy_${module} PROPERTIES EXPORT_NAME ${module})
  if(module IN_LIST CANOPY_CORE_MODULES)
    list(APPEND canopy_core_targets canopy_${module})
  else()
    list(APPEND canopy_sim_targets canopy_${module})
  endif()
endforeach()
# canopy_warnings carries only compile options; static libraries name their private links
# in the export ($<LINK_ONLY:...>), so it is exported too, and adds nothing to a consumer.
set_target_properties(canopy_warnings PROPERTIES EXPORT_NAME warnings)
set_target_properties(canopy_ompl PROPERTIES EXPORT_NAME ompl)

install(TARGETS ${canopy_core_targets} EXPORT canopyTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(EXPORT canopyTargets NAMESPACE canopy:: DESTINATION ${CANOPY_INSTALL_CMAKEDIR})
if(canopy_sim_targets)
  install(TARGETS ${canopy_sim_targets} EXPORT canopySimTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(EXPORT canopySimTargets NAMESPACE canopy:: DESTINATION ${CANOPY_INSTALL_CMAKEDIR})
endif()

install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/canopy DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
# The data the CLI and default_robot_config() look for (data_dir.h): <prefix>/share/canopy.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/models ${PROJECT_SOURCE_DIR}/configs ${PROJECT_SOURCE_DIR}/worlds
                  ${PROJECT_SOURCE_DIR}/web
        DESTINATION ${CMAKE_INSTALL_DATADIR}/canopy)
if(TARGET canopy_cli)
  install(TARGETS canopy_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()

set(CANOPY_DATA_INSTALL_DIR ${CMAKE_INSTALL_DATADIR}/canopy)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/canopyConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/canopyConfig.cmake
                              INSTALL_DESTINATION ${CANOPY_INSTALL_CMAKEDIR}
                              PATH_VARS CANOPY_DATA_INSTALL_DIR)
# 0.x: minor versions may break the interface.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/canopyConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/canopyConfig.cmake ${PROJECT_BINARY_DIR}/canopyConfigVersion.cmake
        DESTINATION ${CANOPY_INSTALL_CMAKEDIR})

if(CANOPY_SANITIZE)
  # An install of a sanitized build: a consumer links the sanitizer runtimes too.
  target_link_options(canopy_common INTERFACE $<INSTALL_INTERFACE:-fsanitize=address,undefined>)
endif()
