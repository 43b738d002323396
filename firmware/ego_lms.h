#ifndef EGO_LMS_H
#define EGO_LMS_H
#endif
