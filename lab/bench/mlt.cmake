# Metropolis benchmark: equal-time relMSE of PT and MLT, mutations/s against path samples/s,
# and the tool that writes the committed door reference (prints JSON; docs/metropolis.md).
if(TARGET glint_render)
  add_executable(bench_mlt ${CMAKE_CURRENT_LIST_DIR}/bench_mlt.cpp)
  target_link_libraries(bench_mlt PRIVATE glint_render nlohmann_json::nlohmann_json)
  glint_warnings(bench_mlt)
endif()
