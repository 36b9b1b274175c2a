# The block-scale bias of the studio's Keep Refining (docs/lab/adaptive-bias.md):
#   build/bin/bench_adaptive_block_bias --scene DIR/scene.json [--steer provisional] [--seeds 24]
# Needs the studio's library for ProgressiveRender's settings and refresh options.
if(GLINT_BUILD_STUDIO)
  add_executable(bench_adaptive_block_bias ${CMAKE_CURRENT_LIST_DIR}/bench_adaptive_block_bias.cpp)
  target_link_libraries(bench_adaptive_block_bias PRIVATE glint_studio nlohmann_json::nlohmann_json)
  glint_warnings(bench_adaptive_block_bias)
endif()
