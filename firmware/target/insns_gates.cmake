# insns_gates.cmake: the gate on each stream's hardest scan, in instructions
# (the '# insns_per_scan ... max=' figure of its replay image), per build
# type: the figure measured on Cortex-M3 and Cortex-M4F (within a few
# hundred instructions of each other: the code is integer-only) plus 2 %.
# QEMU's -icount makes the counts the same run after run, so any growth of
# the estimator's cost fails ctest target_replay_<stream>. When a change
# makes the estimator faster, lower the gates to the new figures (and
# update docs/firmware.md); when it makes it slower on purpose, say why in
# the commit. Streams without a gate for a build type are not checked.
#
#   LMSEGO_INSNS_GATE_<BUILD TYPE>_<stream>         (replay_<stream>, unbounded)
#   LMSEGO_INSNS_GATE_<BUILD TYPE>_budget_<stream>  (budget_<stream>, where set)
#   LMSEGO_INSNS_GATE_<BUILD TYPE>_objects_<stream> (objects_<stream>: within the
#       budget, with the moving objects, ego_moving.h)

# -Os (presets cortex-m3, cortex-m4f): measured 2026-12-02 on Cortex-M3 after
# the full search's projections and tracking registrations (issue 15), plus
# 2.5 % (the M4F's figures were within a few hundred instructions of the
# M3's before), docs/firmware.md. The hardest scans are still the searches:
# the first pair of each stream, the keyframes of the real excerpts, Table
# 2's pair; they fell 6-80 fold (Table 2: 2.53 G -> 102 M); the real
# excerpts, circle and the adversarial stream rose 15-33 % with the sweep's
# second, finer half. Lowered the same day when a rotation whose cells
# score under half the best cell so far stopped costing its neighbourhoods
# and fine grid (ego_coarse.c): intel 122 -> 108 M, aces 114 -> 106 M,
# circle 222 -> 172 M, adversarial 161 -> 128 M, Table 2 102 -> 60 M, busy
# 23.1 -> 20.2 M, fast 33.4 -> 27.6 M. Raised the same day when unbounded
# tracking trimmed its radius to 3 RMS distances (more passes before it is
# still; within the budget nothing grows): campus 1.06 -> 1.24 M, room
# 1.21 -> 1.30 M. Raised 2026-12-03: the adversarial stream's hardest scan
# (the search after its corridor, unbounded) 128 -> 143 M (M3; M4F 144.5 M):
# a corridor tracked with nothing to predict its length leaves the motion
# unknown (commit 6138221), so that search looks over the first window (4 m)
# instead of 1.6 m around a standstill it had only assumed. Lowered the
# same day when a cold start looked along the heading first and an along
# start's measure counted as a prediction along a corridor (no search left
# in either stream): busy 20.2 -> 1.25 M, fast 27.6 -> 2.45 M; gated from
# then on: fast_361_cm_corridor 2.10 M, corridor_361_cm_noise 106 M (M4F).
# Raised the same day by the covariance of every finished registration
# (ego_cov.c, issue 16; charged 6 000 units): busy 1.25 -> 1.30 M, fast
# 2.45 -> 2.53 M, its corridor 2.10 -> 2.17 M, campus 1.24 -> 1.27 M,
# room_181 1.30 -> 1.33 M, corridor_181 0.71 -> 0.73 M (M4F's figures).
# Raised 2026-12-03 (issue 16) for the real excerpts only: replayed here at
# the stream's default period (their keyframes, 3 s apart, taken for 75 Hz
# scans: motions of 40 m/s and 40 rad/s), the weak directions now take the
# prediction's part and the scans are de-skewed with it, a different path
# through the searches: aces 106 -> 148 M, intel 108 -> 121 M (M3). At their
# own spacing (target_keyframes_*) nothing of it applies (intervals over
# 0.2 s). The synthetic streams replay as cast (--sweep instant), but for
# highway_361_cm_mirror (the mirror's timing; gated from its first
# measure, 2.59 M on M3). Raised again the same day for intel: its
# de-skewed points now in their de-skewed bearings' order, its searches
# take another path (121 -> 129 M on M3, 132 M on M4F).
# Raised 2026-12-04 by the objects test (issue 17, docs/estimator.md "Resting on
# objects": each scan's objects marked, their matches' information summed in
# every tracking pass, the test in its result), outputs unchanged: room_361
# 2.34 -> 2.40 M (M3; 2.41 M on M4F), corridor_181 0.731 -> 0.743 M (M3; 0.747 M
# on M4F): the new figures plus 2 %.
set(LMSEGO_INSNS_GATE_MINSIZEREL_adversarial_361_cm 148160000)
set(LMSEGO_INSNS_GATE_MINSIZEREL_aces_0_80 151820000)
set(LMSEGO_INSNS_GATE_MINSIZEREL_busy_181_cm 1332000)
set(LMSEGO_INSNS_GATE_MINSIZEREL_campus_181_cm 1305000)
set(LMSEGO_INSNS_GATE_MINSIZEREL_circle_361_mm_noise 176130000)
set(LMSEGO_INSNS_GATE_MINSIZEREL_corridor_181_cm 762000)
set(LMSEGO_INSNS_GATE_MINSIZEREL_corridor_361_cm_noise 109000000)
set(LMSEGO_INSNS_GATE_MINSIZEREL_fast_361_cm 2598000)
set(LMSEGO_INSNS_GATE_MINSIZEREL_fast_361_cm_corridor 2224000)
set(LMSEGO_INSNS_GATE_MINSIZEREL_highway_361_cm_mirror 2646000)
set(LMSEGO_INSNS_GATE_MINSIZEREL_intel_0_80 134740000)
set(LMSEGO_INSNS_GATE_MINSIZEREL_room_181_mm 1360000)
set(LMSEGO_INSNS_GATE_MINSIZEREL_room_361_cm_faults 2460000)
set(LMSEGO_INSNS_GATE_MINSIZEREL_table2_361_cm 61610000)

# Issue 18's adversarial cases (host_tests/data/recordings/adversarial/), their
# budget images (target_budget_adv_<case>_181_cm: within 600 k a scan, the
# live core's budget for 181 values at 75 Hz): the hardest scan measured
# 2026-12-03 on Cortex-M3 plus 2 %, rounded up to 100 (the M4F's, in the
# comment, are within 1.2 % of the M3's and under every gate). The four cases
# with no point cost the loop's framing, decoding and line alone (39-41 k); the
# others a tracked scan, 'alternating' its search's heaviest step.
set(LMSEGO_INSNS_GATE_MINSIZEREL_budget_adv_all_max_181_cm 470000)  # M3 460760, M4F 462200
set(LMSEGO_INSNS_GATE_MINSIZEREL_budget_adv_alternating_181_cm 525800)  # M3 515480, M4F 521480
set(LMSEGO_INSNS_GATE_MINSIZEREL_budget_adv_collinear_181_cm 477900)  # M3 468480, M4F 469600
set(LMSEGO_INSNS_GATE_MINSIZEREL_budget_adv_invalid_181_cm 40300)  # M3 39440, M4F 39400
set(LMSEGO_INSNS_GATE_MINSIZEREL_budget_adv_one_point_181_cm 40900)  # M3 40080, M4F 40040
set(LMSEGO_INSNS_GATE_MINSIZEREL_budget_adv_one_range_181_cm 481500)  # M3 472000, M4F 473240
set(LMSEGO_INSNS_GATE_MINSIZEREL_budget_adv_repeated_181_cm 467800)  # M3 458600, M4F 459880
set(LMSEGO_INSNS_GATE_MINSIZEREL_budget_adv_specials_181_cm 40300)  # M3 39440, M4F 39400
set(LMSEGO_INSNS_GATE_MINSIZEREL_budget_adv_two_points_181_cm 41400)  # M3 40520, M4F 40480
set(LMSEGO_INSNS_GATE_MINSIZEREL_budget_adv_zigzag_limit_181_cm 469400)  # M3 460160, M4F 461600

# -O2 (presets cortex-m3-o2, cortex-m4f-o2; only the streams outside target_slow;
# measured 2026-11-23, before tracking: they bound the new figures loosely).
set(LMSEGO_INSNS_GATE_RELEASE_campus_181_cm 9700000)
set(LMSEGO_INSNS_GATE_RELEASE_corridor_181_cm 10490000)
set(LMSEGO_INSNS_GATE_RELEASE_fast_361_cm 675620000)
set(LMSEGO_INSNS_GATE_RELEASE_room_181_mm 18390000)
set(LMSEGO_INSNS_GATE_RELEASE_room_361_cm_faults 734110000)
set(LMSEGO_INSNS_GATE_RELEASE_table2_361_cm 2187690000)
# The busy streets (issue 17, host_tests/data/busy), gated from their first
# measurement on Cortex-M3 (2026-12-03) plus 2 %: traffic_181's hardest
# scan is its cold start's search (unbounded), the others' a tracked scan.
# The standstill hold (issue 17, docs/estimator.md "Standing still", 2026-12-03):
# on the platoons the scan held at the "standstill" the trucks suggest ages
# until its tracking fails, and the search that follows (unbounded here) is
# the hardest scan: platoon_181 1.09 -> 91.8 M, platoon_361 2.58 -> 112.3 M
# (M3); stopgo_181's hardest scan a tracked one against the held scan, 0.876
# -> 0.985 M. Gated at those plus 2 %.
# The static structure's own registration (2026-12-05, docs/estimator.md
# "Behind a platoon"): a line on objects no longer leads to a hold and a
# search; the platoons' hardest scans are tracked ones, 91.8 -> 1.58 M
# (181) and 112.3 -> 2.98 M (361) on M3, 1.59 M and 2.99 M on M4F; gated
# at the larger plus 2 %.
set(LMSEGO_INSNS_GATE_MINSIZEREL_platoon_181_cm 1621000)
set(LMSEGO_INSNS_GATE_MINSIZEREL_platoon_361_cm 3050600)
set(LMSEGO_INSNS_GATE_MINSIZEREL_traffic_181_cm 18623000)
set(LMSEGO_INSNS_GATE_MINSIZEREL_traffic_361_cm 2050000)
set(LMSEGO_INSNS_GATE_MINSIZEREL_overtake_181_cm 1198000)
set(LMSEGO_INSNS_GATE_MINSIZEREL_crossing_181_cm 1075000)
set(LMSEGO_INSNS_GATE_MINSIZEREL_pedestrians_181_cm 1135000)
set(LMSEGO_INSNS_GATE_MINSIZEREL_stopgo_181_cm 1005000)

# The busy streets with the moving objects (issue 17 item 3, the objects
# images: estimator within its budget, plus ego_moving_scan and the "o,"
# lines), measured 2026-12-04 on Cortex-M3 -Os, plus 2 % (the M4F within
# 0.8 %).
set(LMSEGO_INSNS_GATE_MINSIZEREL_objects_traffic_181_cm 743400)  # M3 728800
set(LMSEGO_INSNS_GATE_MINSIZEREL_objects_traffic_361_cm 1353300)  # M3 1326800
set(LMSEGO_INSNS_GATE_MINSIZEREL_objects_pedestrians_181_cm 730400)  # M3 716040
set(LMSEGO_INSNS_GATE_MINSIZEREL_objects_crossing_181_cm 657200)  # M3 644320
set(LMSEGO_INSNS_GATE_MINSIZEREL_objects_stopgo_181_cm 656800)  # M3 643920
set(LMSEGO_INSNS_GATE_MINSIZEREL_objects_overtake_181_cm 680800)  # M3 667440
# The platoons' with the static structure's registration (2026-12-05): the
# trucks are found moving now, their clusters tracked (ego_moving_scan up to
# 0.49 M at 181 values, 0.78 M at 361; it was 0.02 M at 361 values while the
# lines rested on the trucks).
set(LMSEGO_INSNS_GATE_MINSIZEREL_objects_platoon_181_cm 968700)  # M3 949040, M4F 949640
set(LMSEGO_INSNS_GATE_MINSIZEREL_objects_platoon_361_cm 1627600)  # M3 1594200, M4F 1595640
