# Simulated LMS 2xx (driver/sim): protocol replies, timing, baud switching,
# streaming, faults and robustness, all on a simulated clock.
lmsego_add_unit_test(test_lms_sim test_lms_sim.c lms_test_util.c)
target_link_libraries(test_lms_sim PRIVATE lms_sim)
