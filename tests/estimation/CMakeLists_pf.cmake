vdtnav_add_test(test_particle_filter SOURCES test_particle_filter.cpp LIBS vdtnav::localization)
