# Every dependency of docs/architecture.md, found from Debian 12 packages
# (installed by scripts/setup.sh). Each is wrapped in an hfts::dep_* target
# so that project targets link one name and get third-party headers as
# SYSTEM includes (their warnings are not ours).

find_package(Threads REQUIRED)
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(PCL 1.13 REQUIRED COMPONENTS common kdtree search features filters sample_consensus)
find_package(CGAL 5.5 REQUIRED)
find_package(embree 3.13 REQUIRED)
find_package(assimp 5.2 REQUIRED)
find_package(HDF5 1.10 REQUIRED COMPONENTS C)
find_package(Qhull 8 REQUIRED)
find_package(fcl 0.7 REQUIRED)
find_package(hwy 1.0 REQUIRED)  # Highway: the sphere tier's SIMD kernel
find_package(ompl 1.5 REQUIRED)
find_package(mujoco 2.2 REQUIRED)  # physics/: does a grasp hold?
find_package(nlohmann_json 3.11 REQUIRED)
find_package(CLI11 2.1 REQUIRED)
find_package(OpenSSL 3 REQUIRED COMPONENTS Crypto SSL)
find_package(tinyxml2 9 REQUIRED)  # SRDF files (robot configs' `srdf`)
find_package(yaml-cpp 0.7 REQUIRED)  # MoveIt planning scenes (MotionBenchMaker)
find_package(PNG 1.6 REQUIRED)  # depth images (robot/point_cloud.h)
find_package(PkgConfig REQUIRED)
pkg_check_modules(URDFDOM REQUIRED IMPORTED_TARGET urdfdom>=3.0)
find_path(ASIO_INCLUDE_DIR asio.hpp REQUIRED)
find_path(NANOFLANN_INCLUDE_DIR nanoflann.hpp REQUIRED)

add_library(hfts_dep_pcl INTERFACE)
target_include_directories(hfts_dep_pcl SYSTEM INTERFACE ${PCL_INCLUDE_DIRS})
target_link_libraries(hfts_dep_pcl INTERFACE ${PCL_LIBRARIES})
add_library(hfts::dep_pcl ALIAS hfts_dep_pcl)

# PCL's PCD and PLY readers (robot/point_cloud.h), linked as the libraries
# themselves: the pcl_io target's interface brings OpenNI, VTK's rendering
# and Qt, none of which the readers need at link time.
find_library(HFTS_PCL_IO pcl_io HINTS ${PCL_LIBRARY_DIRS} REQUIRED)
find_library(HFTS_PCL_IO_PLY pcl_io_ply HINTS ${PCL_LIBRARY_DIRS} REQUIRED)
add_library(hfts_dep_pcl_io INTERFACE)
target_link_libraries(hfts_dep_pcl_io INTERFACE ${HFTS_PCL_IO} ${HFTS_PCL_IO_PLY} hfts_dep_pcl)
add_library(hfts::dep_pcl_io ALIAS hfts_dep_pcl_io)

add_library(hfts_dep_hdf5 INTERFACE)
target_include_directories(hfts_dep_hdf5 SYSTEM INTERFACE ${HDF5_INCLUDE_DIRS})
target_link_libraries(hfts_dep_hdf5 INTERFACE ${HDF5_C_LIBRARIES})
target_compile_definitions(hfts_dep_hdf5 INTERFACE ${HDF5_DEFINITIONS})
add_library(hfts::dep_hdf5 ALIAS hfts_dep_hdf5)

add_library(hfts_dep_asio INTERFACE)
target_include_directories(hfts_dep_asio SYSTEM INTERFACE ${ASIO_INCLUDE_DIR})
# ASIO_DISABLE_STD_ALIGNED_ALLOC: Asio picks aligned_alloc or operator new
# for its handler memory by a libstdc++ macro that depends on what a file
# included first, so files could disagree and memory taken with malloc was
# given back with operator delete (AddressSanitizer: alloc-dealloc-mismatch
# in asio::aligned_delete). One way everywhere: operator new and delete.
target_compile_definitions(hfts_dep_asio INTERFACE ASIO_STANDALONE ASIO_DISABLE_STD_ALIGNED_ALLOC)
target_link_libraries(hfts_dep_asio INTERFACE Threads::Threads)
add_library(hfts::dep_asio ALIAS hfts_dep_asio)

# OMPL (planner framework, nearest neighbours, path simplification).
add_library(hfts_dep_ompl INTERFACE)
target_include_directories(hfts_dep_ompl SYSTEM INTERFACE ${OMPL_INCLUDE_DIR})
target_link_libraries(hfts_dep_ompl INTERFACE ${OMPL_LIBRARIES})
add_library(hfts::dep_ompl ALIAS hfts_dep_ompl)

# nanoflann (header-only k-d tree) for the hand reachability map.
add_library(hfts_dep_nanoflann INTERFACE)
target_include_directories(hfts_dep_nanoflann SYSTEM INTERFACE ${NANOFLANN_INCLUDE_DIR})
add_library(hfts::dep_nanoflann ALIAS hfts_dep_nanoflann)

message(STATUS "hfts: PCL ${PCL_VERSION}, CGAL ${CGAL_VERSION}, Embree ${embree_VERSION}, "
               "assimp ${assimp_VERSION}, HDF5 ${HDF5_VERSION}, FCL ${fcl_VERSION}, "
               "OMPL ${OMPL_VERSION}, urdfdom ${URDFDOM_VERSION}")
