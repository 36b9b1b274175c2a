# Keep refining's refresh intervals and UI stall on a 512² scene (docs/lab/keep-refining.md):
#   QT_QPA_PLATFORM=offscreen build/bin/bench_studio_progressive [--seconds S] [--threads T]
if(GLINT_BUILD_STUDIO)
  find_package(Qt6 6.4 REQUIRED COMPONENTS Test)
  add_executable(bench_studio_progressive ${CMAKE_CURRENT_LIST_DIR}/bench_studio_progressive.cpp)
  target_link_libraries(bench_studio_progressive PRIVATE glint_studio Qt6::Test)
  target_include_directories(bench_studio_progressive PRIVATE ${PROJECT_SOURCE_DIR}/tests/gui)
  target_compile_definitions(bench_studio_progressive PRIVATE GLINT_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  glint_warnings(bench_studio_progressive)
endif()
