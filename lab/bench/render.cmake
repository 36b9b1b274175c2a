# Renderer benchmark: Glint samples/s and rays/s on cornell, and Embree's raw single-ray
# throughput on the same scene (prints JSON; see docs/renderer.md).
if(TARGET glint_render)
  add_executable(bench_render ${CMAKE_CURRENT_LIST_DIR}/bench_render.cpp)
  target_link_libraries(bench_render PRIVATE glint_render nlohmann_json::nlohmann_json)
  # measureRayThroughput is a benchmark hook of renderer/src/renderer_detail.h.
  target_include_directories(bench_render PRIVATE ${CMAKE_SOURCE_DIR}/renderer/src)
  target_compile_definitions(bench_render PRIVATE GLINT_SOURCE_DIR="${CMAKE_SOURCE_DIR}")
  glint_warnings(bench_render)
endif()
