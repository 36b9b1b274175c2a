# The studio's instrumented speed benchmark (docs/studio.md, "Speed"):
#   QT_QPA_PLATFORM=offscreen build/bin/bench_studio [--repeats N]
if(GLINT_BUILD_STUDIO)
  find_package(Qt6 6.4 REQUIRED COMPONENTS Test)
  add_executable(bench_studio ${CMAKE_CURRENT_LIST_DIR}/bench_studio.cpp)
  target_link_libraries(bench_studio PRIVATE glint_studio Qt6::Test)
  # The studio tests' fixture, heavy actions and stall monitor (header-only, tests/gui).
  target_include_directories(bench_studio PRIVATE ${PROJECT_SOURCE_DIR}/tests/gui)
  target_compile_definitions(bench_studio PRIVATE GLINT_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  glint_warnings(bench_studio)
endif()
