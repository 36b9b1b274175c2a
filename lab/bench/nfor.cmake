# NFOR speed (docs/denoise.md, "nfor"):
#   build/bin/bench_nfor [--size 1024] [--spp 4] [--threads 2] [--reps 3]
if(TARGET glint_render)
  add_executable(bench_nfor ${CMAKE_CURRENT_LIST_DIR}/bench_nfor.cpp)
  target_link_libraries(bench_nfor PRIVATE glint_denoise glint_render TBB::tbb
                                           nlohmann_json::nlohmann_json)
  target_compile_definitions(bench_nfor PRIVATE GLINT_SOURCE_DIR="${CMAKE_SOURCE_DIR}")
  glint_warnings(bench_nfor)
endif()
