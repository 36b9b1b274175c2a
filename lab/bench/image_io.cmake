# Layered EXR write + read benchmark (docs/image.md): Google Benchmark.
add_executable(bench_exr_io ${CMAKE_CURRENT_LIST_DIR}/bench_exr_io.cpp)
target_link_libraries(bench_exr_io PRIVATE glint_image benchmark::benchmark)
glint_warnings(bench_exr_io)
