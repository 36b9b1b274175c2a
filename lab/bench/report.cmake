# The speed-versus-accuracy report (docs/tradeoffs.md): glint-report computes the numbers with
# Glint's public API and the bank's sampling helpers (denoise/src/bank/bank_detail.h);
# lab/bench/report/run.sh (make report) runs it and plots the CSVs.
add_executable(glint-report ${CMAKE_CURRENT_LIST_DIR}/report/report.cpp)
target_link_libraries(glint-report PRIVATE glint_render glint_denoise glint_image
                                           nlohmann_json::nlohmann_json TBB::tbb)
target_include_directories(glint-report PRIVATE ${CMAKE_SOURCE_DIR}/denoise/src)
glint_warnings(glint-report)
# A few-second smoke test of the report program (part 5 on a 32x32 render): columns, row count,
# finite values; no blender or matplotlib needed.
add_test(NAME Report.Smoke COMMAND ${CMAKE_CURRENT_LIST_DIR}/report/smoke_test.sh
                                   $<TARGET_FILE:glint-report> ${PROJECT_SOURCE_DIR})
set_tests_properties(Report.Smoke PROPERTIES TIMEOUT 60)
