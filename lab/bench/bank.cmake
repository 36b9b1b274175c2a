# Bank and navigation benchmark (docs/navigation.md, "Speed"):
#   build/bin/bench_bank [--size 1024] [--spp 4] [--threads 2] [--members 64] [--reps 1]
#                        [--retain-freed 1|0]
if(TARGET glint_render)
  add_executable(bench_bank ${CMAKE_CURRENT_LIST_DIR}/bench_bank.cpp)
  target_link_libraries(bench_bank PRIVATE glint_denoise glint_render TBB::tbb
                                           nlohmann_json::nlohmann_json)
  target_compile_definitions(bench_bank PRIVATE GLINT_SOURCE_DIR="${CMAKE_SOURCE_DIR}")
  glint_warnings(bench_bank)
endif()
