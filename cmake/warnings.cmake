# Strict warnings as errors for every target of the project (gcc and clang).
# Applied through an interface library so third-party code (a real Unity)
# is not forced onto our flags.
add_library(lmsego_warnings INTERFACE)
target_compile_options(lmsego_warnings INTERFACE
    -Wall -Wextra -Wpedantic -Werror
    -Wconversion -Wsign-conversion -Wshadow
    -Wmissing-prototypes -Wstrict-prototypes -Wold-style-definition
    -Wcast-qual -Wpointer-arith -Wundef -Wvla -Wwrite-strings
    -Wformat=2
)
