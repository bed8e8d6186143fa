/* numscan.h (private) - fast decimal number scanning for the text readers.
 *
 * mm__scan_double gives exactly the double that strtod gives for the same text (checked against
 * strtod on all the motion capture in the tests), but it reads no locale, needs no terminating
 * zero and is several times faster on the short decimals that fill BVH files: numbers with at
 * most 19 significant digits and a small decimal exponent are converted with one exact IEEE
 * multiplication or division (Clinger's fast path); the rest go through strtod.
 */
#ifndef MM_IO_NUMSCAN_H
#define MM_IO_NUMSCAN_H

#include <stdint.h>

typedef enum mm__scan_status {
    MM__SCAN_OK = 0,
    MM__SCAN_NOT_A_NUMBER, /* p does not start a decimal number */
    MM__SCAN_NOT_FINITE,   /* nan, inf, or a value that overflows a double */
    MM__SCAN_TOO_LONG      /* more than MM__SCAN_MAX_CHARS characters */
} mm__scan_status;

#define MM__SCAN_MAX_CHARS 400

/* Scans [+-]digits[.digits][(e|E)[+-]digits] (or [+-].digits...) starting at p, reading no
 * further than end. On MM__SCAN_OK stores the value and the first unread character. On failure
 * *out_end is the end of the offending token (up to the next space or line end). */
mm__scan_status mm__scan_double(const char *p, const char *end, double *out, const char **out_end);

/* Scans an optional sign and decimal digits into a 64-bit integer; MM__SCAN_NOT_FINITE on
 * overflow. */
mm__scan_status mm__scan_int64(const char *p, const char *end, int64_t *out, const char **out_end);

#endif
