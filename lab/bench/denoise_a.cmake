# Denoise A benchmark: gaussian, exact bilateral, bilateral-mc (+ its accuracy-versus-samples
# curve), with OpenCV side by side when it is installed (benchmark-only peer; glint_denoise never
# links OpenCV). Run: build/bin/bench_denoise_a [--threads 2] [--size 1024] [--reps 9] [--curve 0]
# [--only TEXT] (docs/denoise.md, "Speed and accuracy")
add_executable(bench_denoise_a ${CMAKE_CURRENT_LIST_DIR}/bench_denoise_a.cpp)
target_link_libraries(bench_denoise_a PRIVATE glint_denoise TBB::tbb nlohmann_json::nlohmann_json)
glint_warnings(bench_denoise_a)
find_package(OpenCV QUIET COMPONENTS core imgproc)
if(OpenCV_FOUND)
  target_compile_definitions(bench_denoise_a PRIVATE GLINT_BENCH_HAVE_OPENCV=1)
  target_include_directories(bench_denoise_a SYSTEM PRIVATE ${OpenCV_INCLUDE_DIRS})
  target_link_libraries(bench_denoise_a PRIVATE opencv_core opencv_imgproc)
endif()
