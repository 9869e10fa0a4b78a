# The ROS-free core library, its command-line tools, unit tests and benchmarks.
# Included by CMakeLists.txt in both build modes (catkin, or plain CMake with DE_CORE_ONLY=ON).
# Sources are collected per module folder, so adding a file to src/<module>/ needs no edit here.

find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(OpenCV REQUIRED COMPONENTS core imgproc imgcodecs)
find_package(PCL REQUIRED COMPONENTS common io kdtree search)
find_package(OpenMP)
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
find_library(CHOLMOD_LIBRARY cholmod)

set(DE_CORE_MODULES mesh hermite kinematics descriptors examples enrichment elasticity acquisition scenes shape_space)
set(DE_CORE_SOURCES "")
foreach(module ${DE_CORE_MODULES})
  file(GLOB module_sources CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/${module}/*.cpp)
  list(APPEND DE_CORE_SOURCES ${module_sources})
endforeach()

set(DE_WARNINGS -Wall -Wextra)

add_library(deformation_enrichment_core SHARED ${DE_CORE_SOURCES})
target_compile_features(deformation_enrichment_core PUBLIC cxx_std_17)
target_compile_options(deformation_enrichment_core PRIVATE ${DE_WARNINGS})
target_include_directories(deformation_enrichment_core PUBLIC
  $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>
  $<INSTALL_INTERFACE:include>)
# PCL stays private: no public core header includes it (slow to compile, see docs/design.md).
target_include_directories(deformation_enrichment_core SYSTEM PRIVATE ${PCL_INCLUDE_DIRS})
target_compile_definitions(deformation_enrichment_core PRIVATE ${PCL_DEFINITIONS})
target_link_libraries(deformation_enrichment_core
  PUBLIC Eigen3::Eigen ${OpenCV_LIBS}
  PRIVATE ${PCL_LIBRARIES})
if(OpenMP_CXX_FOUND)
  target_link_libraries(deformation_enrichment_core PUBLIC OpenMP::OpenMP_CXX)
endif()
if(CHOLMOD_INCLUDE_DIR AND CHOLMOD_LIBRARY)
  target_include_directories(deformation_enrichment_core SYSTEM PUBLIC ${CHOLMOD_INCLUDE_DIR})
  target_link_libraries(deformation_enrichment_core PUBLIC ${CHOLMOD_LIBRARY})
  target_compile_definitions(deformation_enrichment_core PUBLIC DE_HAVE_CHOLMOD=1)
endif()

# Command-line tools: src/tools/de_<name>.cpp becomes the executable de_<name>.
file(GLOB DE_TOOL_SOURCES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/tools/de_*.cpp)
set(DE_TOOL_TARGETS "")
foreach(tool_source ${DE_TOOL_SOURCES})
  get_filename_component(tool ${tool_source} NAME_WE)
  add_executable(${tool} ${tool_source})
  target_compile_options(${tool} PRIVATE ${DE_WARNINGS})
  target_link_libraries(${tool} deformation_enrichment_core)
  list(APPEND DE_TOOL_TARGETS ${tool})
endforeach()

# Unit tests (GoogleTest, no ROS master): test/unit/<module>/*.cpp becomes the test unit_<module>.
if(DE_BUILD_TESTS)
  find_package(GTest REQUIRED)
  # Tests that run the command-line tools find them here (catkin puts executables beside each other).
  set(DE_TOOL_DIR "${CMAKE_BINARY_DIR}")
  if(DE_TOOL_TARGETS)
    list(GET DE_TOOL_TARGETS 0 first_tool)
    set(DE_TOOL_DIR "$<TARGET_FILE_DIR:${first_tool}>")
  endif()
  file(GLOB DE_UNIT_DIRS LIST_DIRECTORIES true ${PROJECT_SOURCE_DIR}/test/unit/*)
  foreach(unit_dir ${DE_UNIT_DIRS})
    if(IS_DIRECTORY ${unit_dir})
      get_filename_component(module ${unit_dir} NAME)
      file(GLOB unit_sources CONFIGURE_DEPENDS ${unit_dir}/*.cpp)
      if(unit_sources)
        add_executable(unit_${module} ${unit_sources})
        target_compile_options(unit_${module} PRIVATE ${DE_WARNINGS})
        target_compile_definitions(unit_${module} PRIVATE
          DE_SOURCE_DIR="${PROJECT_SOURCE_DIR}" DE_TOOL_DIR="${DE_TOOL_DIR}")
        target_link_libraries(unit_${module} deformation_enrichment_core GTest::gtest GTest::gtest_main)
        if(DE_TOOL_TARGETS)
          add_dependencies(unit_${module} ${DE_TOOL_TARGETS})
        endif()
        add_test(NAME unit_${module} COMMAND unit_${module}
          --gtest_output=xml:${CMAKE_BINARY_DIR}/test_results/${PROJECT_NAME}/gtest-unit_${module}.xml
          WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
      endif()
    endif()
  endforeach()
endif()

# Benchmarks (Google Benchmark): test/bench/bench_<name>.cpp becomes bench_<name>; run by scripts/bench.
if(DE_BUILD_BENCHMARKS)
  find_package(benchmark REQUIRED)
  file(GLOB DE_BENCH_SOURCES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/test/bench/bench_*.cpp)
  foreach(bench_source ${DE_BENCH_SOURCES})
    get_filename_component(bench ${bench_source} NAME_WE)
    if(NOT bench MATCHES "_ros$")
      add_executable(${bench} ${bench_source})
      target_compile_options(${bench} PRIVATE ${DE_WARNINGS})
      target_link_libraries(${bench} deformation_enrichment_core benchmark::benchmark)
    endif()
  endforeach()
endif()
