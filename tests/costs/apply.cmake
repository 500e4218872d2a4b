# Sets the COST of each (test name, seconds) pair of canopy_test_costs (release.cmake or
# sanitize.cmake, read just before this file).
list(LENGTH canopy_test_costs canopy_n)
math(EXPR canopy_last "${canopy_n} - 1")
foreach(canopy_i RANGE 0 ${canopy_last} 2)
  math(EXPR canopy_j "${canopy_i} + 1")
  list(GET canopy_test_costs ${canopy_i} canopy_name)
  list(GET canopy_test_costs ${canopy_j} canopy_cost)
  set_tests_properties(${canopy_name} PROPERTIES COST ${canopy_cost})
endforeach()
