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
#   LMSEGO_INSNS_GATE_<BUILD TYPE>_<stream>
