# Benchmarks of the cross-bilateral, guided and NL-means filters and the feature prefilter
# (docs/denoise-features.md), with OpenCV's peers side by side when OpenCV is installed
# (libopencv-dev, libopencv-contrib-dev: benchmark only, never linked into glint_denoise).
add_executable(bench_denoise_b ${CMAKE_CURRENT_LIST_DIR}/bench_denoise_b.cpp)
target_link_libraries(bench_denoise_b PRIVATE glint_denoise TBB::tbb benchmark::benchmark)
glint_warnings(bench_denoise_b)
find_package(OpenCV QUIET COMPONENTS core imgproc photo ximgproc)
if(OpenCV_FOUND)
  target_compile_definitions(bench_denoise_b PRIVATE GLINT_BENCH_OPENCV=1)
  target_link_libraries(bench_denoise_b PRIVATE ${OpenCV_LIBS})
endif()
