/* mm/version.h - the library's version: the one place it is kept. CMakeLists.txt reads the three
 * numbers below for the project's version, the shared libraries' SOVERSION, mm.pc and the CMake
 * package's version file; mm_version() returns the version the library was built with.
 *
 * The policy (docs/embedding.md, "Versions"): while the major version is 0, a minor release may
 * change the ABI and the API (the shared libraries' SOVERSION is MAJOR.MINOR: libmm_runtime.so.0.1),
 * a patch release changes neither. From 1.0 on, only a major release does (SOVERSION MAJOR). The
 * .mmdb format has its own number (MM_DB_VERSION, mm/database.h, docs/format.md): a library reads
 * exactly the format version it was built with, and a release that changes the format says so.
 *
 * Functions: mm_version mm_version_string
 */
#ifndef MM_VERSION_H
#define MM_VERSION_H

#ifdef __cplusplus
extern "C" {
#endif

#define MM_VERSION_MAJOR 0
#define MM_VERSION_MINOR 1
#define MM_VERSION_PATCH 0

#define MM_VERSION_STRINGIFY_(x) #x
#define MM_VERSION_STRINGIFY(x)  MM_VERSION_STRINGIFY_(x)
/* "0.1.0" */
#define MM_VERSION_STRING                                                                                    \
    MM_VERSION_STRINGIFY(MM_VERSION_MAJOR)                                                                   \
    "." MM_VERSION_STRINGIFY(MM_VERSION_MINOR) "." MM_VERSION_STRINGIFY(MM_VERSION_PATCH)
/* The version packed in one integer, MAJOR * 10000 + MINOR * 100 + PATCH (0.1.0: 100), to compare:
 * MM_VERSION_NUMBER >= MM_VERSION_PACK(0, 2, 0). */
#define MM_VERSION_PACK(major, minor, patch) ((major)*10000 + (minor)*100 + (patch))
#define MM_VERSION_NUMBER                    MM_VERSION_PACK(MM_VERSION_MAJOR, MM_VERSION_MINOR, MM_VERSION_PATCH)

/* The version of the library linked at run time, packed as MM_VERSION_NUMBER: a program built
 * against one version's headers and run with another's shared library can tell
 * (mm_version() / 100 != MM_VERSION_NUMBER / 100: a different minor version, while the major is 0). */
int mm_version(void);
/* The same as a string, "MAJOR.MINOR.PATCH" (static storage). */
const char *mm_version_string(void);

#ifdef __cplusplus
}
#endif

#endif /* MM_VERSION_H */
