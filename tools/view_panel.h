/* view_panel.h - the viewer's panel (Dear ImGui, in view_panel.cpp), behind a C interface: its
 * windows show what view_ui points at, change the values it points at, and set its requests for
 * the viewer to carry out. Windows: Status, Layers, Tuning, "Why this pose" (the search's
 * candidates) and Timeline. The text is drawn from a TrueType font (DejaVu Sans, when installed;
 * ImGui's own font otherwise) at a size that follows the window's height and the screen's scale. */
#ifndef MM_TOOLS_VIEW_PANEL_H
#define MM_TOOLS_VIEW_PANEL_H

#include <stdbool.h>

#include <GLFW/glfw3.h>

#include <mm/character.h>
#include <mm/view.h>

#include "view_debug.h"

#ifdef __cplusplus
extern "C" {
#endif

enum {
    VIEW_PANEL_STATUS,
    VIEW_PANEL_LAYERS,
    VIEW_PANEL_TUNING,
    VIEW_PANEL_CANDIDATES,
    VIEW_PANEL_TIMELINE,
    VIEW_PANEL_WINDOWS
};

/* Debug drawing beyond mm_view_flags. */
typedef struct view_draws {
    bool ghosts;  /* the candidates' poses beside the character */
    bool preview; /* the selected candidate's clip playing */
} view_draws;

typedef struct view_ui {
    /* shown */
    const mm_character *character;
    const mm_input *input;
    float fps;
    const char *message;
    const char *note; /* a trace's search beside the viewer's (--replay), NULL: none */
    const mm_candidate *candidates;
    int candidate_count;
    int preview_frame;      /* the preview's database frame, -1: none */
    long tick, first, last; /* the tick shown (ticks played), the first and last kept */
    float tick_seconds;
    bool paused;
    bool can_save; /* a config to save into */
    /* changed in place */
    mm_view_tuning *tuning;
    mm_view_flags *flags;
    view_draws *draws;
    int *selected; /* the candidate picked, -1: none */
    /* requests, set this frame */
    bool tuning_changed, layers_changed, toggle_pause, save, reset, select_changed;
    int step_back, step_forward; /* ticks */
    long seek;                   /* a recorded tick to go to, -1: none */
    /* where the windows are this frame: x, y, width, height in framebuffer pixels */
    float rects[VIEW_PANEL_WINDOWS][4];
} view_ui;

typedef struct view_panel view_panel;

/* After the window's callbacks are set (the panel's chain to them). NULL when it cannot start. */
view_panel *view_panel_create(GLFWwindow *window);
void view_panel_destroy(view_panel *p);
/* Lays out and draws the panel over the current framebuffer; clears ui's requests first. */
void view_panel_draw(view_panel *p, view_ui *ui);
/* The panel has the mouse (over a window) or the keyboard (a text field): the 3D view leaves them. */
bool view_panel_wants_mouse(const view_panel *p);
bool view_panel_wants_keyboard(const view_panel *p);

#ifdef __cplusplus
}
#endif

#endif /* MM_TOOLS_VIEW_PANEL_H */
