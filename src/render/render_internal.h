/* render_internal.h - what the render modules share: the font and the OpenGL function table. */
#ifndef MM_RENDER_INTERNAL_H
#define MM_RENDER_INTERNAL_H

#include <stdbool.h>

#include <mm/render.h>

#define MM_FONT_CELL_W 6 /* font pixels per character cell, spacing included */
#define MM_FONT_CELL_H 9
#define MM_FONT_SCALE  2   /* screen pixels per font pixel */
#define MM_FONT_SOLID  127 /* a character code that draws a filled cell (panels) */

/* Whether font pixel (x, y) of character c is set (x right, y down; 5 x 7 glyphs). */
bool mm_font_pixel(int c, int x, int y);

#endif
