/* text.h (private) - locale-independent number formatting for the text writers. */
#ifndef MM_IO_TEXT_H
#define MM_IO_TEXT_H

#include <stddef.h>

/* Writes v with %.*g into buf (size >= 32) using '.' as the decimal point whatever the process
 * locale; -0 is written as 0. Returns the length. */
int mm__format_number(char *buf, size_t size, double v, int precision);

#endif
