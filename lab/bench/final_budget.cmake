# The final auto's cost by plan against glint-final's cost model (docs/lab/race.md, "Keeping the
# time limit"):
#   build/bin/bench_final_budget FRAME.exr [--plans fast,balanced,best,fast:8,fast:1] [--crop 64]
if(TARGET glint_pipeline)
  add_executable(bench_final_budget ${CMAKE_CURRENT_LIST_DIR}/bench_final_budget.cpp)
  target_link_libraries(bench_final_budget PRIVATE glint_pipeline TBB::tbb)
  glint_warnings(bench_final_budget)
endif()
