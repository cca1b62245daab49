# Finds Debian's ROS 1 bag library (librosbag-storage-dev) with what its headers need to read a
# bag and deserialize messages (roscpp_serialization, rostime, cpp_common, console_bridge, Boost
# filesystem), and defines the imported target RosbagStorage::RosbagStorage. Debian's catkin
# config files set variables, not targets; this module gives one target to link and to export.
#
# rosbag/bag.h includes <pluginlib/class_loader.hpp>. Debian ships pluginlib and what it includes
# (class_loader, rcpputils, rcutils, ament_index_cpp) in the ROS 2 layout, one folder deeper
# (/usr/include/pluginlib/pluginlib/class_loader.hpp), so those folders are added as include
# directories too; with the flat ROS 1 layout the same searches find /usr/include.
# The target is GLOBAL so that tests in other folders can write bags with rosbag::Bag.
find_path(RosbagStorage_INCLUDE_DIR rosbag/bag.h)
find_path(RosbagStorage_MSGS_INCLUDE_DIR sensor_msgs/LaserScan.h)
set(_rosbag_storage_dep_dirs)
foreach(dep pluginlib:class_loader.hpp class_loader:class_loader.hpp
            rcpputils:shared_library.hpp rcutils:types.h
            ament_index_cpp:get_package_prefix.hpp)
  string(REPLACE ":" ";" dep "${dep}")
  list(GET dep 0 dir)
  list(GET dep 1 header)
  find_path(RosbagStorage_${dir}_INCLUDE_DIR ${dir}/${header} PATH_SUFFIXES ${dir})
  mark_as_advanced(RosbagStorage_${dir}_INCLUDE_DIR)
  list(APPEND _rosbag_storage_dep_dirs RosbagStorage_${dir}_INCLUDE_DIR)
endforeach()
foreach(lib rosbag_storage roscpp_serialization rostime cpp_common console_bridge)
  find_library(RosbagStorage_${lib}_LIBRARY NAMES ${lib})
  list(APPEND _rosbag_storage_libs RosbagStorage_${lib}_LIBRARY)
endforeach()
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(RosbagStorage REQUIRED_VARS RosbagStorage_INCLUDE_DIR
                                  RosbagStorage_MSGS_INCLUDE_DIR ${_rosbag_storage_dep_dirs}
                                  ${_rosbag_storage_libs})
if(RosbagStorage_FOUND AND NOT TARGET RosbagStorage::RosbagStorage)
  find_package(Boost QUIET REQUIRED COMPONENTS filesystem)
  add_library(RosbagStorage::RosbagStorage INTERFACE IMPORTED GLOBAL)
  set(_libs)
  foreach(v IN LISTS _rosbag_storage_libs)
    list(APPEND _libs "${${v}}")
  endforeach()
  set(_dirs "${RosbagStorage_INCLUDE_DIR}" "${RosbagStorage_MSGS_INCLUDE_DIR}")
  foreach(v IN LISTS _rosbag_storage_dep_dirs)
    list(APPEND _dirs "${${v}}")
  endforeach()
  list(REMOVE_DUPLICATES _dirs)
  # Imported include directories are SYSTEM includes: Debian's ROS headers do not warn in ours.
  set_target_properties(RosbagStorage::RosbagStorage PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${_dirs}"
    INTERFACE_SYSTEM_INCLUDE_DIRECTORIES "${_dirs}"
    INTERFACE_LINK_LIBRARIES "${_libs};Boost::filesystem")
  unset(_libs)
  unset(_dirs)
endif()
mark_as_advanced(RosbagStorage_INCLUDE_DIR RosbagStorage_MSGS_INCLUDE_DIR)
unset(_rosbag_storage_libs)
unset(_rosbag_storage_dep_dirs)
