# Auto memory benchmark (docs/auto-memory.md), run by lab/bench/auto_memory.sh:
#   build/bin/bench_auto_memory --in IN.exr [--mode whole|streamed] [--members 64] [--threads 2]
#                               [--rows 0] [--out OUT.exr] [--against OTHER.exr]
add_executable(bench_auto_memory ${CMAKE_CURRENT_LIST_DIR}/bench_auto_memory.cpp)
target_link_libraries(bench_auto_memory PRIVATE glint_denoise nlohmann_json::nlohmann_json
                                                TBB::tbb)
# The streamed entry with its strip height is private to the library (denoise/src/auto).
target_include_directories(bench_auto_memory PRIVATE ${CMAKE_SOURCE_DIR}/denoise/src)
glint_warnings(bench_auto_memory)
