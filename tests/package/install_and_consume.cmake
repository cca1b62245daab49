# cmake -DBUILD_DIR=... -DWORK_DIR=... -DCONSUMER_DIR=... [-DWITH_CERES=OFF] [-DCONSUME_VIZ=ON]
#       [-DCONSUME_PCL=ON] [-DCONSUME_OCTOMAP=ON] [-DCONSUME_UAV_CAMERA=ON]
#       [-DCONSUME_RGBD_GROUND=ON] [-DCONSUME_ROS=ON] [-DCONSUME_ROS2=ON] [-DROS_NODE=ON] -P install_and_consume.cmake
# CONSUME_<COMPONENT>: also build and run the consumer of that component (only when it was built).
# WITH_CERES=OFF (a build without Ceres): the consumer is configured with Ceres, OpenCV, PCL and
# OctoMap disabled, so it proves the Eigen-only components need none of them, and the
# estimation and mapping consumers check that what needs Ceres says so.
# ROS_NODE: roslaunch's resolver must find the installed vdtnav_localizer as package vdtnav.
foreach(flag WITH_CERES CONSUME_VIZ)
  if(NOT DEFINED ${flag})
    set(${flag} ON)
  endif()
endforeach()
foreach(flag CONSUME_PCL CONSUME_OCTOMAP CONSUME_UAV_CAMERA CONSUME_RGBD_GROUND CONSUME_ROS CONSUME_ROS2)
  if(NOT DEFINED ${flag})
    set(${flag} OFF)
  endif()
endforeach()
file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
endfunction()
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
# No installed header of the Eigen-only layers includes a private dependency (issue 58): a
# consumer of vdtnav::estimation must not need Ceres, one of vdtnav::map not OpenCV; and the study
# fixtures (camera_sim) are not installed.
if(EXISTS ${prefix}/include/vdtnav/camera_sim)
  message(FATAL_ERROR "the study fixture camera_sim was installed: ${prefix}/include/vdtnav/camera_sim")
endif()
foreach(layer core map sensor eval io sim estimation mapping viz map_files ros2)
  file(GLOB_RECURSE headers ${prefix}/include/vdtnav/${layer}/*.hpp)
  foreach(h IN LISTS headers)
    file(STRINGS ${h} private REGEX "^#include <(ceres|opencv2|pcl|octomap|yaml-cpp|ros|tf2|fastcdr|fastdds|fastrtps|sqlite3|suitesparse|cholmod)")
    if(private)
      message(FATAL_ERROR "${h} includes a private dependency: ${private}")
    endif()
  endforeach()
endforeach()
set(consumer_flags "")
set(ceres_arg "")
if(NOT WITH_CERES)
  set(consumer_flags -DCMAKE_DISABLE_FIND_PACKAGE_Ceres=ON -DCMAKE_DISABLE_FIND_PACKAGE_OpenCV=ON
                     -DCMAKE_DISABLE_FIND_PACKAGE_PCL=ON -DCMAKE_DISABLE_FIND_PACKAGE_octomap=ON)
  set(ceres_arg no-ceres)
endif()
run(${CMAKE_COMMAND} -S ${CONSUMER_DIR} -B ${WORK_DIR}/consumer -DCMAKE_PREFIX_PATH=${prefix}
    -DCMAKE_BUILD_TYPE=${CMAKE_BUILD_TYPE} ${consumer_flags} -DVDTNAV_CONSUME_VIZ=${CONSUME_VIZ}
    -DVDTNAV_CONSUME_PCL=${CONSUME_PCL} -DVDTNAV_CONSUME_OCTOMAP=${CONSUME_OCTOMAP}
    -DVDTNAV_CONSUME_UAV_CAMERA=${CONSUME_UAV_CAMERA}
    -DVDTNAV_CONSUME_RGBD_GROUND=${CONSUME_RGBD_GROUND} -DVDTNAV_CONSUME_ROS=${CONSUME_ROS}
    -DVDTNAV_CONSUME_ROS2=${CONSUME_ROS2})
run(${CMAKE_COMMAND} --build ${WORK_DIR}/consumer)
foreach(component core map sensor eval sim map_files)
  run(${WORK_DIR}/consumer/consumer_${component})
endforeach()
foreach(component estimation mapping localization_estimation localization_mapping)
  run(${WORK_DIR}/consumer/consumer_${component} ${ceres_arg})
endforeach()
run(${WORK_DIR}/consumer/consumer_io ${WORK_DIR}/roundtrip.vdtmap)
if(CONSUME_VIZ)
  run(${WORK_DIR}/consumer/consumer_viz ${WORK_DIR}/consumer_viz.png)
endif()
# Without Ceres, vdtnav::estimation's consumer links no Ceres (nor glog, which comes with it).
if(NOT WITH_CERES)
  file(READ ${WORK_DIR}/consumer/CMakeFiles/consumer_estimation.dir/link.txt estimation_link)
  foreach(forbidden ceres glog opencv cholmod)
    string(FIND "${estimation_link}" "${forbidden}" at)
    if(NOT at EQUAL -1)
      message(FATAL_ERROR "vdtnav::estimation's consumer links ${forbidden}: ${estimation_link}")
    endif()
  endforeach()
endif()
# vdtnav::map alone: its link line names no Ceres, OpenCV, PCL or simulator (docs/architecture.md).
file(READ ${WORK_DIR}/consumer/CMakeFiles/consumer_map.dir/link.txt map_link)
foreach(forbidden ceres glog opencv pcl_ octomap vdtnav_sim vdtnav_estimation vdtnav_mapping)
  string(FIND "${map_link}" "${forbidden}" at)
  if(NOT at EQUAL -1)
    message(FATAL_ERROR "vdtnav::map's consumer links ${forbidden}: ${map_link}")
  endif()
endforeach()
string(FIND "${map_link}" "libvdtnav_map.a" at)
if(at EQUAL -1)
  message(FATAL_ERROR "consumer_map's link line does not name libvdtnav_map.a: ${map_link}")
endif()
if(CONSUME_PCL)
  run(${WORK_DIR}/consumer/consumer_pcl ${WORK_DIR}/consumer_cloud.pcd)
  run(${WORK_DIR}/consumer/consumer_point_laser)
endif()
if(CONSUME_OCTOMAP)
  run(${WORK_DIR}/consumer/consumer_octomap ${WORK_DIR}/consumer_tree.bt)
endif()
if(CONSUME_UAV_CAMERA)
  run(${WORK_DIR}/consumer/consumer_camera ${WORK_DIR}/consumer_camera_alone.yaml)
  run(${WORK_DIR}/consumer/consumer_uav_camera ${WORK_DIR}/consumer_camera.yaml)
endif()
if(CONSUME_RGBD_GROUND)
  run(${WORK_DIR}/consumer/consumer_rgbd_ground)
endif()
if(CONSUME_ROS)
  run(${WORK_DIR}/consumer/consumer_ros ${WORK_DIR}/not_a_bag.bag)
endif()
if(CONSUME_ROS2)
  run(${WORK_DIR}/consumer/consumer_ros2)
endif()
if(ROS_NODE)
  # What roslaunch does for <node pkg="vdtnav" type="vdtnav_localizer">, with the prefix on the
  # ROS paths as the README says.
  run(${CMAKE_COMMAND} -E env ROS_PACKAGE_PATH=${prefix}/share CMAKE_PREFIX_PATH=${prefix}
      /usr/bin/python3 -c
      "import sys, roslib.packages as p; f = p.find_node('vdtnav', 'vdtnav_localizer'); \
print(f); sys.exit(0 if f and f[0].startswith('${prefix}') else 1)")
endif()
if(PYTHON_DIR)
  # The Python module, installed into PREFIX/<the interpreter's platlib>: imported from the prefix
  # with it on PYTHONPATH (not from the build tree), and working.
  run(${CMAKE_COMMAND} -E env PYTHONPATH=${prefix}/${PYTHON_DIR} ${PYTHON_EXECUTABLE} -c
      "import sys, numpy as np, vdtnav; f = vdtnav.__file__; print(f); \
m = vdtnav.Map2(np.eye(8, dtype=bool), 0.5); \
sys.exit(0 if f.startswith('${prefix}') and m.lookup(np.zeros((1, 2))).inside[0] else 1)")
  foreach(f __init__.pyi py.typed)
    if(NOT EXISTS ${prefix}/${PYTHON_DIR}/vdtnav/${f})
      message(FATAL_ERROR "the Python package was installed without ${f}")
    endif()
  endforeach()
endif()
# A component that does not exist must make a REQUIRED find fail.
execute_process(COMMAND ${CMAKE_COMMAND} -S ${CONSUMER_DIR} -B ${WORK_DIR}/consumer_bad
                -DCMAKE_PREFIX_PATH=${prefix} -DASK_FOR_MISSING_COMPONENT=ON
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
if(rc EQUAL 0)
  message(FATAL_ERROR "find_package(vdtnav REQUIRED COMPONENTS no_such_component) succeeded")
endif()
message(STATUS "vdtnav installs and is consumable through find_package")
