# Asset benchmark: set-up time and peak memory of a large generated glTF asset (docs/assets.md).
if(TARGET glint_render)
  add_executable(bench_asset_load ${CMAKE_CURRENT_LIST_DIR}/bench_asset_load.cpp)
  target_link_libraries(bench_asset_load PRIVATE glint_render TBB::tbb nlohmann_json::nlohmann_json)
  # accelerationMemory and the scene's mesh arrays: hooks of renderer/src (renderer_detail.h,
  # scene/scene_access.h).
  target_include_directories(bench_asset_load PRIVATE ${CMAKE_SOURCE_DIR}/renderer/src)
  glint_warnings(bench_asset_load)
endif()
