target_sources(bench_estimation PRIVATE ${CMAKE_CURRENT_LIST_DIR}/bench_particle_filter.cpp)
