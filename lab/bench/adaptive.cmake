# Where adaptive sampling's time goes and what an ideal map could gain (docs/lab/adaptive-dof.md,
# "Why adaptive loses on dof"):
#   build/bin/bench_adaptive_throughput [--scene dof] [--seed 21] [--seconds 8] [--threads 2]
if(TARGET glint_render)
  add_executable(bench_adaptive_throughput ${CMAKE_CURRENT_LIST_DIR}/bench_adaptive_throughput.cpp)
  target_link_libraries(bench_adaptive_throughput PRIVATE glint_render)
  target_compile_definitions(bench_adaptive_throughput PRIVATE GLINT_SOURCE_DIR="${CMAKE_SOURCE_DIR}")
  glint_warnings(bench_adaptive_throughput)
endif()
#   build/bin/bench_adaptive_oracle [--scene dof] [--seed 21] [--spp 256] [--pilot 64] [--map-seed 1021] [--cost-block 4] [--exponent 0.5] [--ways ...]
if(TARGET glint_pipeline)
  add_executable(bench_adaptive_oracle ${CMAKE_CURRENT_LIST_DIR}/bench_adaptive_oracle.cpp)
  target_link_libraries(bench_adaptive_oracle PRIVATE glint_pipeline)
  target_compile_definitions(bench_adaptive_oracle PRIVATE GLINT_SOURCE_DIR="${CMAKE_SOURCE_DIR}")
  glint_warnings(bench_adaptive_oracle)
endif()
#   build/bin/bench_adaptive_equal_time [--scenes dof] [--seeds 21,22] [--seconds 12] [--ways uniform,fixed,variance,spread]
if(TARGET glint_pipeline AND TARGET glint_lab)
  add_executable(bench_adaptive_equal_time ${CMAKE_CURRENT_LIST_DIR}/bench_adaptive_equal_time.cpp)
  target_link_libraries(bench_adaptive_equal_time PRIVATE glint_pipeline glint_lab)
  target_compile_definitions(bench_adaptive_equal_time PRIVATE GLINT_SOURCE_DIR="${CMAKE_SOURCE_DIR}")
  glint_warnings(bench_adaptive_equal_time)
endif()
#   build/bin/bench_adaptive_denoised [--scene dof] [--seed 21] [--map-seed 1021] [--spp 1024] [--pilot 64] [--high 4] [--variants default,feather0,stack0,...] [--reference FILE] [--reference2 FILE]
if(TARGET glint_pipeline)
  add_executable(bench_adaptive_denoised ${CMAKE_CURRENT_LIST_DIR}/bench_adaptive_denoised.cpp)
  target_link_libraries(bench_adaptive_denoised PRIVATE glint_pipeline)
  target_compile_definitions(bench_adaptive_denoised PRIVATE GLINT_SOURCE_DIR="${CMAKE_SOURCE_DIR}")
  glint_warnings(bench_adaptive_denoised)
endif()
