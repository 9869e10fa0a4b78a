# The ROS 1 layer: messages, services, nodes, nodelets and rostests, on top of the core (cmake/core.cmake).

set(DE_CATKIN_COMPONENTS
  roscpp message_generation std_msgs std_srvs geometry_msgs sensor_msgs visualization_msgs shape_msgs pcl_msgs
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
  LIBRARIES deformation_enrichment_geometry deformation_enrichment_descriptors deformation_enrichment_runtime
            deformation_enrichment_simulation deformation_enrichment_shape_space deformation_enrichment_ros
            deformation_enrichment_coarse_bag deformation_enrichment_bullet_engine
  CATKIN_DEPENDS roscpp message_runtime std_msgs std_srvs geometry_msgs sensor_msgs visualization_msgs shape_msgs
                 pcl_msgs diagnostic_msgs diagnostic_updater tf2 tf2_ros tf2_eigen tf2_geometry_msgs
                 pcl_conversions urdf nodelet pluginlib dynamic_reconfigure)

set(DE_BUILD_TESTS ${CATKIN_ENABLE_TESTING})
include(cmake/core.cmake)

# The ROS layer library: conversions, parameters, the node class (shared by node and nodelet). It links the
# run-time layer only: the enrichment node and nodelet never load the simulator or shape space.
file(GLOB DE_ROS_SOURCES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/ros/lib/*.cpp)
add_library(deformation_enrichment_ros SHARED ${DE_ROS_SOURCES})
target_compile_options(deformation_enrichment_ros PRIVATE ${DE_WARNINGS})
target_include_directories(deformation_enrichment_ros SYSTEM PUBLIC ${catkin_INCLUDE_DIRS})
target_include_directories(deformation_enrichment_ros PUBLIC ${PROJECT_SOURCE_DIR}/include)
target_link_libraries(deformation_enrichment_ros deformation_enrichment_runtime ${catkin_LIBRARIES})
add_dependencies(deformation_enrichment_ros ${PROJECT_NAME}_generate_messages_cpp ${PROJECT_NAME}_gencfg
  ${catkin_EXPORTED_TARGETS})

de_no_undefined(deformation_enrichment_ros)

add_library(deformation_enrichment_nodelets SHARED src/ros/enrichment_nodelet.cpp)
target_compile_options(deformation_enrichment_nodelets PRIVATE ${DE_WARNINGS})
target_link_libraries(deformation_enrichment_nodelets deformation_enrichment_ros)

# Nodes (src/ros/<name>_node.cpp becomes <name>_node) and ROS command-line tools (src/ros/de_<name>.cpp
# becomes de_<name>): the ROS library plus the core layers each one includes (the demo scene the simulator,
# the shape-space server and de_smooth_bag the shape space).
file(GLOB DE_NODE_SOURCES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/ros/*_node.cpp ${PROJECT_SOURCE_DIR}/src/ros/de_*.cpp
  ${PROJECT_SOURCE_DIR}/src/ros/acquisition_driver.cpp)
set(DE_NODE_TARGETS "")
foreach(node_source ${DE_NODE_SOURCES})
  get_filename_component(node ${node_source} NAME_WE)
  add_executable(${node} ${node_source})
  target_compile_options(${node} PRIVATE ${DE_WARNINGS})
  target_link_libraries(${node} deformation_enrichment_ros)
  de_link_core_for(${node} ${node_source})
  list(APPEND DE_NODE_TARGETS ${node})
endforeach()

# Recordings of a coarse simulator (docs/coarse_simulator.md): acquisition_driver writes them, de_make_examples and
# de_evaluate --coarse-bag read them (the option exists in the catkin build only). A library of its own: it links the
# simulation layer, which the ROS layer library and the enrichment node never load.
add_library(deformation_enrichment_coarse_bag SHARED src/ros/coarse_bag/coarse_bag.cpp)
target_compile_options(deformation_enrichment_coarse_bag PRIVATE ${DE_WARNINGS})
target_link_libraries(deformation_enrichment_coarse_bag deformation_enrichment_ros deformation_enrichment_simulation)
de_no_undefined(deformation_enrichment_coarse_bag)
target_link_libraries(acquisition_driver deformation_enrichment_coarse_bag)
foreach(tool de_make_examples de_evaluate)
  target_link_libraries(${tool} deformation_enrichment_coarse_bag)
  target_compile_definitions(${tool} PRIVATE DE_COARSE_BAG=1)
endforeach()

install(TARGETS ${DE_CORE_LIBRARIES} deformation_enrichment_ros deformation_enrichment_nodelets deformation_enrichment_coarse_bag
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  RUNTIME DESTINATION ${CATKIN_GLOBAL_BIN_DESTINATION})
install(TARGETS ${DE_NODE_TARGETS} ${DE_TOOL_TARGETS} RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
install(DIRECTORY include/${PROJECT_NAME}/ DESTINATION ${CATKIN_PACKAGE_INCLUDE_DESTINATION})
install(DIRECTORY launch config DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})
install(DIRECTORY ${DE_GENERATED_SCENE_DIR}/ DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION}/config/scenes OPTIONAL)
install(FILES nodelet_plugins.xml DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})

# Benchmarks that need a ROS master (run by scripts/bench, which starts one).
if(DE_BUILD_BENCHMARKS)
  file(GLOB DE_ROS_BENCH_SOURCES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/test/bench/bench_*_ros.cpp)
  foreach(bench_source ${DE_ROS_BENCH_SOURCES})
    get_filename_component(bench ${bench_source} NAME_WE)
    add_executable(${bench} ${bench_source})
    target_compile_options(${bench} PRIVATE ${DE_WARNINGS})
    target_link_libraries(${bench} deformation_enrichment_ros benchmark::benchmark)
    de_link_core_for(${bench} ${bench_source})
    add_dependencies(${bench} enrichment_node deformation_enrichment_nodelets)
  endforeach()
endif()

# Integration tests against a real master (rostest starts one per test file).
if(CATKIN_ENABLE_TESTING)
  find_package(rostest REQUIRED)
  # de_rostest_gtest(<target> <launch file> SOURCES <test/ros sources> DEPENDS <targets the launch file runs>)
  function(de_rostest_gtest target launch)
    cmake_parse_arguments(ARG "" "" "SOURCES;DEPENDS" ${ARGN})
    add_rostest_gtest(${target} ${launch} ${ARG_SOURCES})
    target_compile_options(${target} PRIVATE ${DE_WARNINGS})
    target_link_libraries(${target} deformation_enrichment_ros)
    list(TRANSFORM ARG_SOURCES PREPEND ${PROJECT_SOURCE_DIR}/)
    de_link_core_for(${target} ${ARG_SOURCES} ${PROJECT_SOURCE_DIR}/test/ros/enrichment_node_fixture.hpp)
    add_dependencies(${target} ${ARG_DEPENDS})
  endfunction()
  de_rostest_gtest(test_enrichment_node test/ros/enrichment_node.test SOURCES test/ros/test_enrichment_node.cpp
    DEPENDS enrichment_node deformation_enrichment_nodelets)
  add_rostest(test/ros/enrichment_nodelet.test DEPENDENCIES test_enrichment_node)
  de_rostest_gtest(test_enrichment_knobs test/ros/enrichment_knobs.test
    SOURCES test/ros/test_enrichment_knobs.cpp test/ros/test_tool_pose_sources.cpp test/ros/test_parameter.cpp
    test/ros/test_enrichment_markers.cpp DEPENDS enrichment_node deformation_enrichment_nodelets)
  add_rostest(test/ros/enrichment_knobs_nodelet.test DEPENDENCIES test_enrichment_knobs)
  add_rostest(test/ros/demo.test DEPENDENCIES ${DE_NODE_TARGETS})
  add_rostest(test/ros/demo_simulator_truth.test DEPENDENCIES ${DE_NODE_TARGETS})
  set_tests_properties(_ctest_${PROJECT_NAME}_rostest_test_ros_demo.test PROPERTIES
    FIXTURES_REQUIRED slab_set ENVIRONMENT DE_TEST_SLAB_SET=${DE_TEST_SLAB_SET})
  # rosrun / roslaunch as a user runs them, from the devel space's environment.
  set(DE_RUN_EXECUTABLES "")
  foreach(exe ${DE_NODE_TARGETS} ${DE_TOOL_TARGETS})
    list(APPEND DE_RUN_EXECUTABLES $<TARGET_FILE_NAME:${exe}>)
  endforeach()
  add_test(NAME rosrun_roslaunch COMMAND ${CATKIN_DEVEL_PREFIX}/env.sh bash ${PROJECT_SOURCE_DIR}/test/ros/rosrun_roslaunch.sh
    ${CATKIN_DEVEL_PREFIX}/${CATKIN_PACKAGE_BIN_DESTINATION} ${PROJECT_SOURCE_DIR}/test/data/slab_tap.bag ${DE_RUN_EXECUTABLES})
  # The master restarts under a running enrichment.launch (process and nodelet): respawned, registered, configured.
  add_test(NAME master_restart COMMAND ${CATKIN_DEVEL_PREFIX}/env.sh bash ${PROJECT_SOURCE_DIR}/test/ros/master_restart.sh)
  set_tests_properties(master_restart PROPERTIES ENVIRONMENT ROS_HOME=${CMAKE_BINARY_DIR}/ros_home TIMEOUT 600)
  # The README's own-workspace path (catkin_make in a fresh catkin_ws), from a clean environment.
  add_test(NAME catkin_workspace COMMAND env -i PATH=/usr/bin:/bin HOME=$ENV{HOME} ROS_HOME=${CMAKE_BINARY_DIR}/ros_home
    bash ${PROJECT_SOURCE_DIR}/test/ros/catkin_workspace.sh ${PROJECT_SOURCE_DIR})
  set_tests_properties(catkin_workspace PROPERTIES TIMEOUT 1800)
  add_test(NAME layers COMMAND /usr/bin/python3 ${PROJECT_SOURCE_DIR}/test/layers/check_layers.py ${DE_LAYER_CHECKS}
    $<TARGET_FILE:deformation_enrichment_ros>=simulation,shape_space,bullet_engine
    $<TARGET_FILE:deformation_enrichment_nodelets>=simulation,shape_space,bullet_engine
    $<TARGET_FILE:enrichment_node>=simulation,shape_space,bullet_engine)
  de_rostest_gtest(test_recorded_sequence test/ros/recorded_sequence.test SOURCES test/ros/test_recorded_sequence.cpp
    DEPENDS enrichment_node)
  de_rostest_gtest(test_live_stream_node test/ros/live_stream.test SOURCES test/ros/test_live_stream_node.cpp
    test/accuracy/live_stream_scenario.hpp DEPENDS enrichment_node)
  set_tests_properties(_ctest_${PROJECT_NAME}_rostest_test_ros_live_stream.test PROPERTIES
    FIXTURES_REQUIRED slab_set ENVIRONMENT DE_TEST_SLAB_SET=${DE_TEST_SLAB_SET})
  de_rostest_gtest(test_open_surface_node test/ros/open_surface.test SOURCES test/ros/test_open_surface_node.cpp
    DEPENDS enrichment_node)
  set_tests_properties(_ctest_${PROJECT_NAME}_rostest_test_ros_open_surface.test PROPERTIES
    FIXTURES_REQUIRED slab_set ENVIRONMENT DE_TEST_SLAB_SET=${DE_TEST_SLAB_SET})
  # Recordings of a coarse simulator, written and read without a master.
  add_executable(test_coarse_bag test/ros/test_coarse_bag.cpp)
  target_compile_options(test_coarse_bag PRIVATE ${DE_WARNINGS})
  target_link_libraries(test_coarse_bag deformation_enrichment_coarse_bag GTest::gtest)
  add_test(NAME test_coarse_bag COMMAND test_coarse_bag
    --gtest_output=xml:${CMAKE_BINARY_DIR}/test_results/${PROJECT_NAME}/gtest-test_coarse_bag.xml)
  # acquisition_driver against a stand-in simulator (the contract without physics).
  add_executable(fake_coarse_sim test/ros/fake_coarse_sim.cpp)
  target_compile_options(fake_coarse_sim PRIVATE ${DE_WARNINGS})
  target_link_libraries(fake_coarse_sim deformation_enrichment_ros)
  add_rostest(test/ros/acquisition_driver.test DEPENDENCIES fake_coarse_sim acquisition_driver de_make_examples)
  de_rostest_gtest(test_shape_space_server test/ros/shape_space_server.test SOURCES test/ros/test_shape_space_server.cpp
    test/unit/shape_space/real_sequences.hpp
    DEPENDS ${DE_NODE_TARGETS})
  # The node under load for a minute (scripts/soak --minutes M runs it for longer).
  add_executable(soak_driver test/ros/soak_driver.cpp)
  target_compile_options(soak_driver PRIVATE ${DE_WARNINGS})
  target_link_libraries(soak_driver deformation_enrichment_ros)
  add_test(NAME soak COMMAND ${CATKIN_DEVEL_PREFIX}/env.sh bash ${PROJECT_SOURCE_DIR}/scripts/soak --minutes 1
    --example-set ${DE_TEST_SLAB_SET} --no-build)
  set_tests_properties(soak PROPERTIES FIXTURES_REQUIRED slab_set TIMEOUT 600)
  add_dependencies(soak_driver enrichment_node)
  # The Bullet coarse simulator speaks the contract of docs/coarse_simulator.md.
  de_rostest_gtest(test_bullet_coarse_sim test/ros/bullet_coarse_sim.test SOURCES test/ros/test_bullet_coarse_sim.cpp
    DEPENDS bullet_coarse_sim_node)
  # Examples made against Bullet over ROS beat the own-SNH set on Bullet's held-out states.
  add_rostest(test/ros/coarse_simulator.test
    DEPENDENCIES bullet_coarse_sim_node acquisition_driver de_make_examples de_evaluate)
  set_tests_properties(_ctest_${PROJECT_NAME}_rostest_test_ros_coarse_simulator.test PROPERTIES
    FIXTURES_REQUIRED slab_auto_set ENVIRONMENT DE_TEST_SLAB_AUTO_SET=${DE_TEST_SLAB_AUTO_SET})
  # ctest runs in parallel (scripts/test: one test per core), except these: the tests against a master (their
  # rates, timeouts and the soak's latencies assume the machine to themselves) and the second build of the
  # package. Each rostest starts its own master on a free port, so the Bullet examples test, which waits for
  # settled states rather than on the clock and keeps one core busy for two minutes, runs beside the unit tests
  # (its cost starts it first).
  get_property(de_tests DIRECTORY PROPERTY TESTS)
  list(FILTER de_tests INCLUDE REGEX "rostest|^rosrun_roslaunch$|^master_restart$|^catkin_workspace$|^soak$")
  list(FILTER de_tests EXCLUDE REGEX "rostest_test_ros_coarse_simulator\\.test$")
  set_tests_properties(${de_tests} PROPERTIES RUN_SERIAL TRUE)
  set_tests_properties(_ctest_${PROJECT_NAME}_rostest_test_ros_coarse_simulator.test PROPERTIES COST 1000)
endif()
