# SSIM benchmark (docs/metrics.md): a JSON-printing driver; lab/bench/ssim_skimage.py runs it
# and times scikit-image on the same images.
add_executable(bench_ssim ${CMAKE_CURRENT_LIST_DIR}/bench_ssim.cpp)
target_link_libraries(bench_ssim PRIVATE glint_image TBB::tbb nlohmann_json::nlohmann_json)
glint_warnings(bench_ssim)
# FLIP benchmark (docs/lab/flip.md): a JSON-printing driver, LDR and HDR at 1024x1024.
add_executable(bench_flip ${CMAKE_CURRENT_LIST_DIR}/bench_flip.cpp)
target_link_libraries(bench_flip PRIVATE glint_image TBB::tbb nlohmann_json::nlohmann_json)
glint_warnings(bench_flip)
