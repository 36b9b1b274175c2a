# Painting-session benchmarks (docs/painting.md, "Speed"): brush dabs and strokes, Poisson
# diffusion, and Eigen's conjugate gradients on the same problem (Eigen: benchmark and tests
# only, never linked into glint_denoise).
#   build/bin/bench_session [--size=1024] [--ichol] [--benchmark_repetitions=5]
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
add_executable(bench_session ${CMAKE_CURRENT_LIST_DIR}/bench_session.cpp)
target_link_libraries(bench_session PRIVATE glint_denoise TBB::tbb Eigen3::Eigen
                                            benchmark::benchmark)
glint_warnings(bench_session)
