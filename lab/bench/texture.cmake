# Texture benchmark: an asset with four 2048² tiled MIP-mapped EXR textures rendered textured
# and untextured, in interleaved pairs, with a texture cache of a quarter of their size (prints
# JSON; docs/assets.md, "Speed and memory of textures").
if(TARGET glint_render)
  add_executable(bench_texture ${CMAKE_CURRENT_LIST_DIR}/bench_texture.cpp)
  target_link_libraries(bench_texture PRIVATE glint_render OpenImageIO::OpenImageIO
                                              nlohmann_json::nlohmann_json)
  glint_warnings(bench_texture)
endif()
