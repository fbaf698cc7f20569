# skygraph_aces_reference: the reference ACES RRT + ODT through OpenColorIO's built-in
# transforms (bench/aces_reference.hpp), which tests/math pins and bench's study and aces_fits
# use. The top level includes it when tests are built; bench includes it otherwise.
if(NOT TARGET skygraph_aces_reference)
  find_package(PkgConfig REQUIRED)
  pkg_check_modules(OCIO IMPORTED_TARGET GLOBAL OpenColorIO>=2.1)
  if(NOT OCIO_FOUND)
    message(FATAL_ERROR "OpenColorIO >= 2.1 (pkg-config 'OpenColorIO') not found: the reference ACES "
                        "transform of study and math_tests needs it. On Debian 12: apt install "
                        "libopencolorio-dev (tools/install-deps.sh installs it).")
  endif()
  pkg_check_modules(LCMS2 REQUIRED IMPORTED_TARGET GLOBAL lcms2)
  add_library(skygraph_aces_reference STATIC ${CMAKE_CURRENT_LIST_DIR}/aces_reference.cpp)
  target_include_directories(skygraph_aces_reference PUBLIC ${CMAKE_CURRENT_LIST_DIR})
  target_link_libraries(skygraph_aces_reference PUBLIC skygraph_math PRIVATE PkgConfig::OCIO PkgConfig::LCMS2
                        skygraph_warnings)
endif()
