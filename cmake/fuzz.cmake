# libFuzzer harnesses for every loader of outside data (test/fuzz/fuzz_<reader>.cpp), built with clang when
# DE_CORE_ONLY=ON and DE_FUZZ=ON; scripts/fuzz configures, builds and runs them.
# The core sources the loaders need are compiled here once more with the sanitizers and the coverage
# instrumentation, so this file needs nothing from cmake/core.cmake (which is not included in this mode).

if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  message(FATAL_ERROR "DE_FUZZ needs clang's libFuzzer: configure with -DCMAKE_C_COMPILER=clang-14 -DCMAKE_CXX_COMPILER=clang++-14")
endif()

find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(OpenCV REQUIRED COMPONENTS core)
find_package(PCL REQUIRED COMPONENTS common io)
find_package(VTK REQUIRED COMPONENTS CommonCore CommonDataModel FiltersCore ImagingGeneral IOLegacy IOXML)
find_package(ZLIB REQUIRED)
find_package(yaml-cpp REQUIRED)

# -O1 -g whatever the build type, and assertions stay on (-UNDEBUG: Eigen's index checks;
# _GLIBCXX_ASSERTIONS: bounds-checked std::vector / std::string): a failed assertion is a finding too.
# No sanitizer recovers: the first report ends the run with a crash the fuzzer saves.
set(DE_FUZZ_SANITIZERS -fsanitize=address,undefined -fno-sanitize-recover=all)
set(DE_FUZZ_FLAGS -O1 -g -fno-omit-frame-pointer -UNDEBUG -D_GLIBCXX_ASSERTIONS ${DE_FUZZ_SANITIZERS} -Wall -Wextra)

# The loaders and the files they call into, no more (the link fails if a loader comes to need another):
# mesh/ (OBJ, PLY, OFF, STL, TetGen, gmsh, VTK, MD2, point-cloud layout; PCL only for writing), hermite/ +
# examples/ + scene_file/ (example sets and their provenance, scene files) and the plan CSV. The rest of
# mesh/ (CGAL's surface repair alone compiles for over a minute) is left out for CI's time.
set(DE_FUZZ_CORE_SOURCES "")
foreach(source
    mesh/gmsh_io mesh/md2_reader mesh/mesh_io mesh/obj_reader mesh/off_reader mesh/ply_reader
    mesh/point_cloud_layout mesh/tet_collector mesh/tet_mesh mesh/tetgen_io mesh/triangle_mesh mesh/volume_mesh_io
    mesh/vtk_io mesh/vtk_legacy_reader
    hermite/hermite_basis hermite/moment_list hermite/multi_index hermite/symmetric_tensor
    examples/example examples/example_set_io scene_file/scene_description scene_file/scene_yaml acquisition/plan_io)
  list(APPEND DE_FUZZ_CORE_SOURCES ${PROJECT_SOURCE_DIR}/src/${source}.cpp)
endforeach()

add_library(de_fuzz_core STATIC ${DE_FUZZ_CORE_SOURCES})
target_compile_options(de_fuzz_core PRIVATE ${DE_FUZZ_FLAGS} -fsanitize=fuzzer-no-link)
target_include_directories(de_fuzz_core PUBLIC ${PROJECT_SOURCE_DIR}/include)
target_include_directories(de_fuzz_core SYSTEM PRIVATE ${PCL_INCLUDE_DIRS})
target_compile_definitions(de_fuzz_core PRIVATE ${PCL_DEFINITIONS})
target_compile_definitions(de_fuzz_core PRIVATE CGAL_USE_ZLIB DE_GENERATED_SCENE_DIR="" DE_INSTALL_SCENE_DIR=""
  DE_SOURCE_SCENE_DIR="${PROJECT_SOURCE_DIR}/config/scenes")
target_link_libraries(de_fuzz_core PUBLIC Eigen3::Eigen ${OpenCV_LIBS} PRIVATE ${PCL_LIBRARIES} VTK::CommonCore
  VTK::CommonDataModel VTK::FiltersCore VTK::ImagingGeneral VTK::IOLegacy VTK::IOXML ZLIB::ZLIB yaml-cpp)
target_link_options(de_fuzz_core INTERFACE ${DE_FUZZ_SANITIZERS})

# Writes the seeds that are cheaper to generate than to keep in git (an example set, clouds, a tiny MD2).
add_executable(fuzz_make_seeds ${PROJECT_SOURCE_DIR}/test/fuzz/make_seeds.cpp)
target_compile_options(fuzz_make_seeds PRIVATE ${DE_FUZZ_FLAGS})
target_link_libraries(fuzz_make_seeds de_fuzz_core)

file(GLOB DE_FUZZ_HARNESSES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/test/fuzz/fuzz_*.cpp)
foreach(harness_source ${DE_FUZZ_HARNESSES})
  get_filename_component(harness ${harness_source} NAME_WE)
  add_executable(${harness} ${harness_source})
  target_compile_options(${harness} PRIVATE ${DE_FUZZ_FLAGS} -fsanitize=fuzzer)
  target_link_options(${harness} PRIVATE -fsanitize=fuzzer)
  target_link_libraries(${harness} de_fuzz_core)
endforeach()
