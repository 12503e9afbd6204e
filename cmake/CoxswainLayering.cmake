# SPDX-License-Identifier: Apache-2.0
# Dependencies point inward. These checks run at configure time and stop the build when a library
# reaches one it must not (directly or through what it links), so the layering cannot rot.

# Collects every target `target` links, transitively, into `out_var`.
function(coxswain_collect_links target out_var)
  set(seen "")
  set(queue ${target})
  while(queue)
    list(POP_FRONT queue current)
    if(NOT TARGET ${current} OR current IN_LIST seen)
      continue()
    endif()
    list(APPEND seen ${current})
    get_target_property(type ${current} TYPE)
    set(links "")
    if(NOT type STREQUAL "INTERFACE_LIBRARY")
      get_target_property(direct ${current} LINK_LIBRARIES)
      if(direct)
        list(APPEND links ${direct})
      endif()
    endif()
    get_target_property(iface ${current} INTERFACE_LINK_LIBRARIES)
    if(iface)
      list(APPEND links ${iface})
    endif()
    foreach(link IN LISTS links)
      string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" link "${link}")
      if(TARGET ${link})
        list(APPEND queue ${link})
      endif()
    endforeach()
  endwhile()
  set(${out_var} ${seen} PARENT_SCOPE)
endfunction()

# coxswain_forbid_links(TARGETS a b ... FORBIDDEN x y ...)
function(coxswain_forbid_links)
  cmake_parse_arguments(ARG "" "" "TARGETS;FORBIDDEN" ${ARGN})
  foreach(target IN LISTS ARG_TARGETS)
    if(NOT TARGET ${target})
      continue()
    endif()
    coxswain_collect_links(${target} reached)
    foreach(bad IN LISTS ARG_FORBIDDEN)
      if(bad IN_LIST reached)
        message(FATAL_ERROR "layering: ${target} links ${bad} (directly or through a dependency)")
      endif()
    endforeach()
  endforeach()
endfunction()

# Drivers know their device, not the engines.
coxswain_forbid_links(
  TARGETS coxswain_drivers_serial coxswain_drivers_rplidar coxswain_drivers_myahrs
          coxswain_drivers_ublox coxswain_drivers_arduino
  FORBIDDEN coxswain_guidance coxswain_control coxswain_mission coxswain_config yaml-cpp)
# The core is pure: no file format, no logging, no OpenCV, no I/O library.
coxswain_forbid_links(
  TARGETS coxswain_mission coxswain_guidance coxswain_control coxswain_perception_lidar
          coxswain_config_model
  FORBIDDEN coxswain_config yaml-cpp spdlog::spdlog coxswain_opencv coxswain_perception_vision
            coxswain_app coxswain_live coxswain_record)
# Replay and the simulator's recorder need the hosts' shared records, not the daemon.
coxswain_forbid_links(TARGETS coxswain_replay coxswain_host coxswain_record coxswain_sim_recording
                      FORBIDDEN coxswain_app)
