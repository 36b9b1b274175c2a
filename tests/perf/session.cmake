# Painting benchmark (docs/painting.md, "Speed"): brush dabs, Poisson diffusion and Eigen's
# conjugate gradients on the same problem.
#   build/bin/bench_session [--size 1024] [--threads 2] [--eigen 1]
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
add_executable(bench_session ${CMAKE_CURRENT_LIST_DIR}/bench_session.cpp)
target_link_libraries(bench_session PRIVATE glint_denoise TBB::tbb Eigen3::Eigen
                                            nlohmann_json::nlohmann_json)
glint_warnings(bench_session)
