# Labels every test case of ggg_tests `fast` or `slow` (ctest -L fast, ctest -L slow). ctest
# includes this file after the test cases that gtest_discover_tests found (their names are in
# ggg_tests_TESTS); see native/tests/CMakeLists.txt.
#
# `slow` are the cases that take more than about a minute in the sanitizers' build
# (scripts/sanitize.sh, which runs only the `fast` ones; docs/reliability.md): learning and
# decoding whole cities, and the few tests that learn a city's grammar first. The learning of
# a city is fast only for the small extracts listed here; a city added to ../shared/osm is
# `slow` until measured.
set(ggg_corpus_fast_cities
  aguascalientes_mx_osm_pbf barcelona_eixample_osm krems_at_osm_gz monaco_osm_pbf
  moscow_north_osm_gz oakland_west_osm_bz2 paris_marais_osm_pbf rome_centre_osm)
set(ggg_slow_tests
  IsogroupDetection.PrunedFindsTheLeadingPatternsOfTheFullAnalysisOnBarcelona
  StreetHierarchy.MainRoadsOfColumbusMeetAcrossAGrownStrip
  Growth.AGrownRegionHasTheStyleOfItsCity
  GrammarLearning.DeterministicWhateverTheThreadCount)

# (list(FIND) rather than if(IN_LIST): ctest reads this file with the policies of CMake 2.x.)
foreach(ggg_test IN LISTS ggg_tests_TESTS)
  set(ggg_label fast)
  list(FIND ggg_slow_tests "${ggg_test}" ggg_at)
  if(ggg_at GREATER -1)
    set(ggg_label slow)
  elseif(ggg_test MATCHES "^SharedOsm/(Lossless|Paper)Corpus\\.[A-Za-z]+/([A-Za-z0-9_]+)")
    list(FIND ggg_corpus_fast_cities "${CMAKE_MATCH_2}" ggg_at)
    if(ggg_at EQUAL -1)
      set(ggg_label slow)
    endif()
  endif()
  set_tests_properties("${ggg_test}" PROPERTIES LABELS ${ggg_label})
endforeach()
