/* ego_lms.c - see ego_lms.h. */
#include "ego_lms.h"

typedef int ego_lms_placeholder_t;
