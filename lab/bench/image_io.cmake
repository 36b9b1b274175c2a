# Layered EXR write + read benchmark (docs/image.md): Google Benchmark, OpenImageIO the peer.
add_executable(bench_exr_io ${CMAKE_CURRENT_LIST_DIR}/bench_exr_io.cpp)
target_link_libraries(bench_exr_io PRIVATE glint_image benchmark::benchmark OpenImageIO::OpenImageIO)
glint_warnings(bench_exr_io)
# PNG and JPEG read (libpng, libjpeg-turbo) beside OpenImageIO reading the same files.
add_executable(bench_png_jpeg_io ${CMAKE_CURRENT_LIST_DIR}/bench_png_jpeg_io.cpp)
target_link_libraries(bench_png_jpeg_io PRIVATE glint_image benchmark::benchmark OpenImageIO::OpenImageIO)
glint_warnings(bench_png_jpeg_io)
