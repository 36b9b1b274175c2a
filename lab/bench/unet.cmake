# The learned filter unet's speed and memory (docs/learned.md):
#   build/bin/bench_unet [--size 1024] [--spp 16] [--threads 2] [--reps 3] [--quality 1]
#   /usr/bin/time -v build/bin/bench_unet --width 3840 --height 2160 --reps 1
if(TARGET glint_render)
  add_executable(bench_unet ${CMAKE_CURRENT_LIST_DIR}/bench_unet.cpp)
  target_link_libraries(bench_unet PRIVATE glint_denoise glint_render TBB::tbb DNNL::dnnl
                                           OpenMP::OpenMP_CXX nlohmann_json::nlohmann_json)
  target_include_directories(bench_unet PRIVATE ${CMAKE_CURRENT_LIST_DIR}
                                                ${CMAKE_SOURCE_DIR}/denoise/src)
  target_compile_definitions(bench_unet PRIVATE GLINT_SOURCE_DIR="${CMAKE_SOURCE_DIR}")
  glint_warnings(bench_unet)
endif()
