# Installs Glint so that another project writes find_package(Glint CONFIG REQUIRED) and links
# Glint::image, Glint::render, Glint::denoise (docs/embedding.md). The libraries are static; the
# package config finds their private dependencies (TBB, OpenEXR, Embree, tinyobjloader).
include(CMakePackageConfigHelpers)

# Libraries built with sanitizers (make test-sanitize) need the sanitizer runtimes in whatever
# links them: the installed targets carry the link option.
if(GLINT_SANITIZE)
  foreach(lib glint_image glint_render glint_denoise)
    target_link_options(${lib} INTERFACE -fsanitize=address,undefined)
  endforeach()
endif()
# Glint's modules (the image formats other than OpenEXR, the renderer's texture cache), where
# glint_image looks for them (image/src/modules.cpp).
install(TARGETS glint_image_formats glint_textures LIBRARY DESTINATION ${GLINT_MODULE_INSTALL_DIR})
install(TARGETS glint_image glint_render glint_denoise
        EXPORT GlintTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
foreach(module image renderer denoise)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${module}/include/glint
          DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endforeach()
# The learned filter's weights (and their licence), where weightsDir() looks beside bin/.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/denoise/weights/oidn/
        DESTINATION ${GLINT_UNET_WEIGHTS_INSTALL_DIR}
        FILES_MATCHING PATTERN "*.tza" PATTERN "LICENSE.txt")
foreach(tool glint-image glint-render glint-denoise glint-final)
  if(TARGET ${tool})
    install(TARGETS ${tool} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  endif()
endforeach()

set(GLINT_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/Glint)
install(EXPORT GlintTargets NAMESPACE Glint:: DESTINATION ${GLINT_CMAKE_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/GlintConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/GlintConfig.cmake
                              INSTALL_DESTINATION ${GLINT_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/GlintConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/GlintConfig.cmake ${PROJECT_BINARY_DIR}/GlintConfigVersion.cmake
        DESTINATION ${GLINT_CMAKE_DIR})
