# Labels every test case of ggg_tests `fast` or `slow` (ctest -L fast, ctest -L slow), and
# `unit`, `corpus` or `cli` by what it needs (ggg_corpus_tests and ggg_cli_tests, from
# test_kinds.cmake; a test that needs both is `corpus` and `cli`). ctest includes this file
# after the test cases that gtest_discover_tests found (their names are in ggg_tests_TESTS);
# see native/tests/CMakeLists.txt.
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
  Growth.CrowdedJunctionsAreThinnedAndOffsetPairsJoined
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
  # Suite.Name, also of a parameterised case (Instance/Suite.Name/parameter).
  set(ggg_case "${ggg_test}")
  if(ggg_test MATCHES "^[A-Za-z0-9_]+/([A-Za-z0-9_]+\\.[A-Za-z0-9_]+)/")
    set(ggg_case "${CMAKE_MATCH_1}")
  endif()
  set(ggg_kinds "")
  list(FIND ggg_corpus_tests "${ggg_case}" ggg_at)
  if(ggg_at GREATER -1)
    list(APPEND ggg_kinds corpus)
  endif()
  list(FIND ggg_cli_tests "${ggg_case}" ggg_at)
  if(ggg_at GREATER -1)
    list(APPEND ggg_kinds cli)
  endif()
  if(NOT ggg_kinds)
    set(ggg_kinds unit)
  endif()
  set_tests_properties("${ggg_test}" PROPERTIES LABELS "${ggg_label};${ggg_kinds}")
endforeach()
