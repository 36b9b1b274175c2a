# Auto start benchmark (docs/auto.md, "Speed"):
#   build/bin/bench_auto [--estimator sure|halves] [--one-sided 0|1] [--size 1024] [--spp 4] [--threads 2] [--members 64] [--reps 3]
if(TARGET glint_render)
  add_executable(bench_auto ${CMAKE_CURRENT_LIST_DIR}/bench_auto.cpp)
  target_link_libraries(bench_auto PRIVATE glint_denoise glint_render TBB::tbb
                                           nlohmann_json::nlohmann_json)
  target_compile_definitions(bench_auto PRIVATE GLINT_SOURCE_DIR="${CMAKE_SOURCE_DIR}")
  glint_warnings(bench_auto)
endif()

# Each member's halves estimate against its true error per tile (docs/lab/oidn-gap.md,
# section 4): build/bin/auto_member_errors IN.exr BANK REFERENCE.exr [--tile 32]
add_executable(auto_member_errors ${CMAKE_CURRENT_LIST_DIR}/auto_member_errors.cpp)
target_link_libraries(auto_member_errors PRIVATE glint_denoise TBB::tbb)
target_include_directories(auto_member_errors PRIVATE ${CMAKE_SOURCE_DIR}/denoise/src)
glint_warnings(auto_member_errors)
