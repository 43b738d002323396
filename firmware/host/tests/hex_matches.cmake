# hex_matches.cmake - checks that the binary file BIN holds exactly the
# bytes written as hex in the text file HEX ('#' comments and whitespace
# ignored).   cmake -DHEX=f.hex -DBIN=f.lms -P hex_matches.cmake
cmake_minimum_required(VERSION 3.21)
file(STRINGS ${HEX} lines)
set(want "")
foreach(line IN LISTS lines)
    string(REGEX REPLACE "#.*$" "" line "${line}")
    string(REGEX REPLACE "[ \t]" "" line "${line}")
    string(APPEND want "${line}")
endforeach()
string(TOLOWER "${want}" want)
file(READ ${BIN} got HEX)
if(NOT got STREQUAL want)
    message(FATAL_ERROR "${BIN} does not hold the bytes of ${HEX}")
endif()
