# Finds what a ROS 1 node needs from Debian (libroscpp-dev, libtf2-ros-dev, libstd-srvs-dev,
# libdiagnostic-msgs-dev and the message packages) and defines the imported target
# Ros1Node::Ros1Node. Debian's catkin config files for these packages need catkin itself, which
# Debian does not ship as a CMake package: this module looks for the headers and libraries.
find_path(Ros1Node_INCLUDE_DIR ros/ros.h)
find_path(Ros1Node_TF2_ROS_INCLUDE_DIR tf2_ros/transform_broadcaster.h)
find_path(Ros1Node_STD_SRVS_INCLUDE_DIR std_srvs/Empty.h)
find_path(Ros1Node_DIAGNOSTIC_INCLUDE_DIR diagnostic_msgs/DiagnosticStatus.h)
find_path(Ros1Node_MSGS_INCLUDE_DIR nav_msgs/GetMap.h)
set(_ros1_node_libs)
foreach(lib roscpp rosconsole roscpp_serialization rostime cpp_common xmlrpcpp tf2_ros tf2)
  find_library(Ros1Node_${lib}_LIBRARY NAMES ${lib})
  mark_as_advanced(Ros1Node_${lib}_LIBRARY)
  list(APPEND _ros1_node_libs Ros1Node_${lib}_LIBRARY)
endforeach()
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(Ros1Node REQUIRED_VARS Ros1Node_INCLUDE_DIR
                                  Ros1Node_TF2_ROS_INCLUDE_DIR Ros1Node_STD_SRVS_INCLUDE_DIR
                                  Ros1Node_DIAGNOSTIC_INCLUDE_DIR Ros1Node_MSGS_INCLUDE_DIR
                                  ${_ros1_node_libs})
if(Ros1Node_FOUND AND NOT TARGET Ros1Node::Ros1Node)
  find_package(Boost QUIET REQUIRED COMPONENTS system thread)
  add_library(Ros1Node::Ros1Node INTERFACE IMPORTED GLOBAL)
  set(_libs)
  foreach(v IN LISTS _ros1_node_libs)
    list(APPEND _libs "${${v}}")
  endforeach()
  set(_dirs "${Ros1Node_INCLUDE_DIR}" "${Ros1Node_TF2_ROS_INCLUDE_DIR}"
            "${Ros1Node_STD_SRVS_INCLUDE_DIR}" "${Ros1Node_DIAGNOSTIC_INCLUDE_DIR}"
            "${Ros1Node_MSGS_INCLUDE_DIR}")
  list(REMOVE_DUPLICATES _dirs)
  # SYSTEM includes: Debian's ROS headers do not warn in ours.
  set_target_properties(Ros1Node::Ros1Node PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${_dirs}"
    INTERFACE_SYSTEM_INCLUDE_DIRECTORIES "${_dirs}"
    INTERFACE_LINK_LIBRARIES "${_libs};Boost::system;Boost::thread")
  unset(_libs)
  unset(_dirs)
endif()
mark_as_advanced(Ros1Node_INCLUDE_DIR Ros1Node_TF2_ROS_INCLUDE_DIR Ros1Node_STD_SRVS_INCLUDE_DIR
                 Ros1Node_DIAGNOSTIC_INCLUDE_DIR Ros1Node_MSGS_INCLUDE_DIR)
unset(_ros1_node_libs)
