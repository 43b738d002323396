# measure.cmake: included from CMakeLists.txt (cross builds).
