# Strict warnings as errors (LMSEGO_WERROR, on when lmsego is the top-level
# project) for every target of the project (gcc and clang).
# Applied through an interface library linked PRIVATE, so third-party code
# (a real Unity) and projects that use lmsego are not forced onto our flags.
# A static library's PRIVATE links still appear in its exported link
# interface ($<LINK_ONLY:lmsego_warnings>), so cmake/install.cmake installs
# this target too: its flags are BUILD_INTERFACE only, installed it is empty.
set(LMSEGO_WARNING_FLAGS
    -Wall -Wextra -Wpedantic
    -Wconversion -Wsign-conversion -Wshadow
    -Wmissing-prototypes -Wstrict-prototypes -Wold-style-definition
    -Wcast-qual -Wpointer-arith -Wundef -Wvla -Wwrite-strings
    -Wformat=2
)
# gcc's static analyzer (issue 18): its findings are warnings too. Slow (about
# half a minute of CPU for the shipped code): CI builds only the shipped
# targets with it (.ci/run, preset analyzer), not the tests.
if(LMSEGO_ANALYZER)
    list(APPEND LMSEGO_WARNING_FLAGS -fanalyzer)
endif()
if(LMSEGO_WERROR)
    list(APPEND LMSEGO_WARNING_FLAGS -Werror)
endif()
add_library(lmsego_warnings INTERFACE)
target_compile_options(lmsego_warnings INTERFACE "$<BUILD_INTERFACE:${LMSEGO_WARNING_FLAGS}>")
