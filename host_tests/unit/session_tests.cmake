# The session state machine against the simulated scanner, in-process.
lmsego_add_unit_test(test_lms_session test_lms_session.c lms_test_util.c)
target_link_libraries(test_lms_session PRIVATE lms_sim)
