# The final auto's cost by plan against glint-final's cost model (docs/lab/race.md, "Keeping the
# time limit"):
#   build/bin/bench_final_budget FRAME.exr [--plans balanced,fast,fast:8,fast:1,cheapest] [--runs 2]
#   build/bin/bench_final_budget FRAME.exr --study 3     # the probe's spread by crop
#   build/bin/bench_final_budget FRAME.exr --crop 0 --warmup fast:1 --plans cheapest,balanced,balanced
if(TARGET glint_pipeline)
  add_executable(bench_final_budget ${CMAKE_CURRENT_LIST_DIR}/bench_final_budget.cpp)
  target_link_libraries(bench_final_budget PRIVATE glint_pipeline TBB::tbb)
  glint_warnings(bench_final_budget)
endif()
