/* The library's version at run time (mm/version.h). */
#include "mm/version.h"

int mm_version(void) { return MM_VERSION_NUMBER; }

const char *mm_version_string(void) { return MM_VERSION_STRING; }
