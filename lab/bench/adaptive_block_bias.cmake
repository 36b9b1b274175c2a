# The block-scale bias of the studio's Keep Refining (docs/lab/adaptive-bias.md):
#   build/bin/bench_adaptive_block_bias --scene DIR/scene.json [--steer provisional] [--seeds 24]
if(TARGET glint_pipeline)
  add_executable(bench_adaptive_block_bias ${CMAKE_CURRENT_LIST_DIR}/bench_adaptive_block_bias.cpp)
  target_link_libraries(bench_adaptive_block_bias PRIVATE glint_pipeline nlohmann_json::nlohmann_json)
  glint_warnings(bench_adaptive_block_bias)
endif()
