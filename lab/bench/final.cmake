# The final render at equal time: uniform, fixed-threshold adaptive, variance-scheduled and
# denoiser-steered adaptive sampling, each followed by auto, relMSE against the scenes'
# references (docs/lab/adaptive-sampling.md, "Equal time after auto"):
#   build/bin/bench_final [--scenes glossy,dof,cornell] [--seeds 21,22] [--seconds 15,30] [--threads 2] [--ways …]
if(TARGET glint_pipeline)
  add_executable(bench_final ${CMAKE_CURRENT_LIST_DIR}/bench_final.cpp)
  target_link_libraries(bench_final PRIVATE glint_pipeline)
  target_compile_definitions(bench_final PRIVATE GLINT_SOURCE_DIR="${CMAKE_SOURCE_DIR}")
  glint_warnings(bench_final)
endif()
