# What every nodelet package of the stack writes in its CMakeLists.txt, once (sl_params' CFG_EXTRAS:
# every nodelet package finds sl_params already). In a package:
#   sl_add_nodelets(<pkg>_nodelets src/nodelets/<name>_nodelet.cpp LIBRARIES <pkg>_core)
#   sl_add_node(<name>_node)
#   sl_install_package(LIBRARIES <pkg>_core <pkg>_nodelets PROGRAMS <name>_node SHARE launch config)

# sl_add_nodelets(<target> <source>... [LIBRARIES <lib>...] [INCLUDE_DIRS <dir>...]): the library of
# a package's nodelets (the ROS wrappers of its core, given in LIBRARIES), built against catkin's
# headers and libraries.
function(sl_add_nodelets target)
  cmake_parse_arguments(ARG "" "" "LIBRARIES;INCLUDE_DIRS" ${ARGN})
  add_library(${target} ${ARG_UNPARSED_ARGUMENTS})
  target_include_directories(${target} PRIVATE ${ARG_INCLUDE_DIRS} ${catkin_INCLUDE_DIRS})
  target_link_libraries(${target} ${ARG_LIBRARIES} ${catkin_LIBRARIES})
endfunction()

# sl_add_node(<name>): the executable <name> of src/nodes/<name>.cpp, a node that only loads its
# nodelet (doc/CONVENTIONS.md), built against catkin's headers and libraries.
function(sl_add_node name)
  add_executable(${name} src/nodes/${name}.cpp)
  target_include_directories(${name} PRIVATE ${catkin_INCLUDE_DIRS})
  target_link_libraries(${name} ${catkin_LIBRARIES})
endfunction()

# sl_install_package([LIBRARIES <target>...] [PROGRAMS <target>...] [SHARE <file or dir>...])
# LIBRARIES: libraries, into the package's lib folder. PROGRAMS: executables, into the package's
# lib folder (rosrun). SHARE: files and folders (relative to the package) into its share folder.
# Also include/<package>/ and nodelet_plugins.xml, where the package has them.
function(sl_install_package)
  cmake_parse_arguments(ARG "" "" "LIBRARIES;PROGRAMS;SHARE" ${ARGN})
  if(ARG_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "sl_install_package: unknown arguments ${ARG_UNPARSED_ARGUMENTS}")
  endif()
  if(ARG_LIBRARIES)
    install(TARGETS ${ARG_LIBRARIES}
      ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
      LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
      RUNTIME DESTINATION ${CATKIN_GLOBAL_BIN_DESTINATION})
  endif()
  if(ARG_PROGRAMS)
    install(TARGETS ${ARG_PROGRAMS} RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
  endif()
  if(IS_DIRECTORY ${PROJECT_SOURCE_DIR}/include/${PROJECT_NAME})
    install(DIRECTORY include/${PROJECT_NAME}/ DESTINATION ${CATKIN_PACKAGE_INCLUDE_DESTINATION})
  endif()
  set(_share)
  if(EXISTS ${PROJECT_SOURCE_DIR}/nodelet_plugins.xml)
    list(APPEND _share nodelet_plugins.xml)
  endif()
  foreach(_item ${ARG_SHARE})
    if(IS_DIRECTORY ${PROJECT_SOURCE_DIR}/${_item})
      install(DIRECTORY ${_item} DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})
    else()
      list(APPEND _share ${_item})
    endif()
  endforeach()
  if(_share)
    install(FILES ${_share} DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})
  endif()
endfunction()
