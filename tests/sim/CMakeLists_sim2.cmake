# Dataset 1 simulator (thesis 3.4.1): tour planner, trajectory, LiDAR + odometry simulator.
# The planner and simulator tests also run on the Stage hospital section when the data is present.
vdtnav_add_test(test_route_planner SOURCES test_route_planner.cpp LIBS vdtnav::io)
vdtnav_add_test(test_trajectory SOURCES test_trajectory.cpp LIBS vdtnav::core)
vdtnav_add_test(test_lidar_simulator SOURCES test_lidar_simulator.cpp LIBS vdtnav::io)
