# The speed-versus-accuracy report (docs/tradeoffs.md): glint-report computes the numbers with
# Glint's public API; tests/perf/report/run.sh (make report) runs it and plots the CSVs.
add_executable(glint-report ${CMAKE_CURRENT_LIST_DIR}/report/report.cpp)
target_link_libraries(glint-report PRIVATE glint_render glint_denoise glint_image
                                           nlohmann_json::nlohmann_json TBB::tbb)
glint_warnings(glint-report)
