# The ROS 1 layer: messages, services, nodes, nodelets and rostests, on top of the core (cmake/core.cmake).

set(DE_CATKIN_COMPONENTS
  roscpp message_generation std_msgs geometry_msgs sensor_msgs visualization_msgs shape_msgs pcl_msgs
  diagnostic_msgs diagnostic_updater tf2 tf2_ros tf2_eigen tf2_geometry_msgs pcl_conversions urdf nodelet pluginlib rosbag dynamic_reconfigure)
find_package(catkin REQUIRED COMPONENTS ${DE_CATKIN_COMPONENTS})

add_message_files(DIRECTORY msg FILES ToolContact.msg ToolContactArray.msg EnrichmentStatus.msg)
add_service_files(DIRECTORY srv FILES LoadExampleSet.srv SegmentSites.srv SmoothSequence.srv ComputeGeodesic.srv
  BezierCurve.srv)
generate_messages(DEPENDENCIES std_msgs geometry_msgs sensor_msgs pcl_msgs)
# Run-time knobs of the enrichment node (header deformation_enrichment/EnrichmentConfig.h).
generate_dynamic_reconfigure_options(cfg/Enrichment.cfg)

catkin_package(
  INCLUDE_DIRS include
  LIBRARIES deformation_enrichment_core deformation_enrichment_ros
  CATKIN_DEPENDS roscpp message_runtime std_msgs geometry_msgs sensor_msgs visualization_msgs shape_msgs
                 pcl_msgs diagnostic_msgs diagnostic_updater tf2 tf2_ros tf2_eigen tf2_geometry_msgs
                 pcl_conversions urdf nodelet pluginlib dynamic_reconfigure)

set(DE_BUILD_TESTS ${CATKIN_ENABLE_TESTING})
include(cmake/core.cmake)

# The ROS layer library: conversions, parameters, the node class (shared by node and nodelet).
file(GLOB DE_ROS_SOURCES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/ros/lib/*.cpp)
add_library(deformation_enrichment_ros SHARED ${DE_ROS_SOURCES})
target_compile_options(deformation_enrichment_ros PRIVATE ${DE_WARNINGS})
target_include_directories(deformation_enrichment_ros SYSTEM PUBLIC ${catkin_INCLUDE_DIRS})
target_include_directories(deformation_enrichment_ros PUBLIC ${PROJECT_SOURCE_DIR}/include)
target_link_libraries(deformation_enrichment_ros deformation_enrichment_core ${catkin_LIBRARIES})
add_dependencies(deformation_enrichment_ros ${PROJECT_NAME}_generate_messages_cpp ${PROJECT_NAME}_gencfg
  ${catkin_EXPORTED_TARGETS})

add_library(deformation_enrichment_nodelets SHARED src/ros/enrichment_nodelet.cpp)
target_compile_options(deformation_enrichment_nodelets PRIVATE ${DE_WARNINGS})
target_link_libraries(deformation_enrichment_nodelets deformation_enrichment_ros)

# Nodes: src/ros/<name>_node.cpp becomes the executable <name>_node.
file(GLOB DE_NODE_SOURCES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/ros/*_node.cpp)
set(DE_NODE_TARGETS "")
foreach(node_source ${DE_NODE_SOURCES})
  get_filename_component(node ${node_source} NAME_WE)
  add_executable(${node} ${node_source})
  target_compile_options(${node} PRIVATE ${DE_WARNINGS})
  target_link_libraries(${node} deformation_enrichment_ros)
  list(APPEND DE_NODE_TARGETS ${node})
endforeach()

# ROS command-line tools (rosbag and friends): src/ros/de_<name>.cpp becomes de_<name>.
file(GLOB DE_ROS_TOOL_SOURCES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/ros/de_*.cpp)
foreach(tool_source ${DE_ROS_TOOL_SOURCES})
  get_filename_component(tool ${tool_source} NAME_WE)
  add_executable(${tool} ${tool_source})
  target_compile_options(${tool} PRIVATE ${DE_WARNINGS})
  target_link_libraries(${tool} deformation_enrichment_ros)
  list(APPEND DE_NODE_TARGETS ${tool})
endforeach()

install(TARGETS deformation_enrichment_core deformation_enrichment_ros deformation_enrichment_nodelets
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  RUNTIME DESTINATION ${CATKIN_GLOBAL_BIN_DESTINATION})
install(TARGETS ${DE_NODE_TARGETS} ${DE_TOOL_TARGETS} RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
install(DIRECTORY include/${PROJECT_NAME}/ DESTINATION ${CATKIN_PACKAGE_INCLUDE_DESTINATION})
install(DIRECTORY launch config DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})
install(FILES nodelet_plugins.xml DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})

# Benchmarks that need a ROS master (run by scripts/bench, which starts one).
if(DE_BUILD_BENCHMARKS)
  file(GLOB DE_ROS_BENCH_SOURCES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/test/bench/bench_*_ros.cpp)
  foreach(bench_source ${DE_ROS_BENCH_SOURCES})
    get_filename_component(bench ${bench_source} NAME_WE)
    add_executable(${bench} ${bench_source})
    target_compile_options(${bench} PRIVATE ${DE_WARNINGS})
    target_link_libraries(${bench} deformation_enrichment_ros)
    add_dependencies(${bench} enrichment_node deformation_enrichment_nodelets)
  endforeach()
endif()

# Integration tests against a real master (rostest starts one per test file).
if(CATKIN_ENABLE_TESTING)
  find_package(rostest REQUIRED)
  add_rostest_gtest(test_enrichment_node test/ros/enrichment_node.test test/ros/test_enrichment_node.cpp)
  target_compile_options(test_enrichment_node PRIVATE ${DE_WARNINGS})
  target_link_libraries(test_enrichment_node deformation_enrichment_ros)
  add_dependencies(test_enrichment_node enrichment_node deformation_enrichment_nodelets)
  add_rostest(test/ros/enrichment_nodelet.test DEPENDENCIES test_enrichment_node)
  add_rostest_gtest(test_enrichment_knobs test/ros/enrichment_knobs.test test/ros/test_enrichment_knobs.cpp
    test/ros/test_tool_tip.cpp)
  target_compile_options(test_enrichment_knobs PRIVATE ${DE_WARNINGS})
  target_link_libraries(test_enrichment_knobs deformation_enrichment_ros)
  add_dependencies(test_enrichment_knobs enrichment_node deformation_enrichment_nodelets)
  add_rostest(test/ros/enrichment_knobs_nodelet.test DEPENDENCIES test_enrichment_knobs)
  add_rostest(test/ros/demo.test DEPENDENCIES ${DE_NODE_TARGETS})
  add_rostest_gtest(test_recorded_sequence test/ros/recorded_sequence.test test/ros/test_recorded_sequence.cpp)
  target_compile_options(test_recorded_sequence PRIVATE ${DE_WARNINGS})
  target_link_libraries(test_recorded_sequence deformation_enrichment_ros)
  add_dependencies(test_recorded_sequence enrichment_node)
  add_rostest_gtest(test_shape_space_server test/ros/shape_space_server.test test/ros/test_shape_space_server.cpp)
  target_compile_options(test_shape_space_server PRIVATE ${DE_WARNINGS})
  target_link_libraries(test_shape_space_server deformation_enrichment_ros)
  add_dependencies(test_shape_space_server ${DE_NODE_TARGETS})
endif()
