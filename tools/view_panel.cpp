// The viewer's panel: Dear ImGui windows over the 3D view (see view_panel.h).
#include "view_panel.h"

#include <cmath>
#include <cstdio>
#include <cstring>

#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include <mm/gait.h>

// The font: DejaVu Sans where Debian's fonts-dejavu-core puts it, ImGui's own otherwise.
static const char *const font_path = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
static const float font_pixels = 16.0f;       // at a window 720 pixels high
static const float reference_height = 720.0f; // the window height the sizes are designed at
static const float min_scale = 0.75f, max_scale = 3.0f;
static const float column_fraction = 0.3f; // of the window's width, each side column

struct view_panel {
    GLFWwindow *window;
    float scale;                // of the font and sizes, as last built
    float display_w, display_h; // the window size the layout was made for
};

// The panel's scale for the window: its height against the reference, in steps of 1/8 (the font is
// built again only when it changes), times the screen's content scale.
static float scale_for(GLFWwindow *w)
{
    int ww = 0, wh = 0;
    glfwGetWindowSize(w, &ww, &wh);
    float sx = 1.0f, sy = 1.0f;
    glfwGetWindowContentScale(w, &sx, &sy);
    float s = (float)wh / reference_height * (sy > 0.0f ? sy : 1.0f);
    s = s < min_scale ? min_scale : s > max_scale ? max_scale : s;
    return std::round(s * 8.0f) / 8.0f;
}

static void build_font(view_panel *p, float scale)
{
    ImGuiIO &io = ImGui::GetIO();
    int ww = 0, fw = 0, h = 0;
    glfwGetWindowSize(p->window, &ww, &h);
    glfwGetFramebufferSize(p->window, &fw, &h);
    float density = ww > 0 && fw > 0 ? (float)fw / (float)ww : 1.0f; // framebuffer pixels per window unit
    io.Fonts->Clear();
    float pixels = std::round(font_pixels * scale * density);
    ImFont *font = NULL;
    if (FILE *f = std::fopen(font_path, "rb")) {
        std::fclose(f);
        font = io.Fonts->AddFontFromFileTTF(font_path, pixels);
    }
    if (!font) {
        ImFontConfig config;
        config.SizePixels = pixels;
        io.Fonts->AddFontDefault(&config);
    }
    io.FontGlobalScale = 1.0f / density;
    ImGui_ImplOpenGL3_DestroyFontsTexture();
    ImGui_ImplOpenGL3_CreateFontsTexture();
    ImGuiStyle style;
    ImGui::StyleColorsDark(&style);
    style.WindowRounding = 4.0f;
    style.ScaleAllSizes(scale);
    ImGui::GetStyle() = style;
    p->scale = scale;
}

view_panel *view_panel_create(GLFWwindow *window)
{
    IMGUI_CHECKVERSION();
    if (!ImGui::CreateContext()) return NULL;
    ImGuiIO &io = ImGui::GetIO();
    io.IniFilename = NULL; // the layout is the viewer's, the same every run
    if (!ImGui_ImplGlfw_InitForOpenGL(window, true)) {
        ImGui::DestroyContext();
        return NULL;
    }
    if (!ImGui_ImplOpenGL3_Init("#version 330 core")) {
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
        return NULL;
    }
    view_panel *p = new view_panel();
    p->window = window;
    build_font(p, scale_for(window));
    return p;
}

void view_panel_destroy(view_panel *p)
{
    if (!p) return;
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    delete p;
}

bool view_panel_wants_mouse(const view_panel *p) { return p && ImGui::GetIO().WantCaptureMouse; }
bool view_panel_wants_keyboard(const view_panel *p) { return p && ImGui::GetIO().WantCaptureKeyboard; }

// ---- windows ----

static void place(const view_ui *, int which, float x, float y, float w, float h, ImGuiCond cond)
{
    (void)which;
    ImGui::SetNextWindowPos(ImVec2(x, y), cond);
    ImGui::SetNextWindowSize(ImVec2(w, h), cond);
}

static void note_rect(view_ui *ui, int which)
{
    ImVec2 pos = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
    ImVec2 density = ImGui::GetIO().DisplayFramebufferScale;
    ui->rects[which][0] = pos.x * density.x;
    ui->rects[which][1] = pos.y * density.y;
    ui->rects[which][2] = size.x * density.x;
    ui->rects[which][3] = size.y * density.y;
}

static const char *playback_name(mm_character_playback p)
{
    switch (p) {
    case MM_PLAYBACK_CLOCK:
        return "clock";
    case MM_PLAYBACK_DISTANCE:
        return "distance";
    case MM_PLAYBACK_STOP:
        return "stop";
    case MM_PLAYBACK_PIVOT:
        return "pivot";
    case MM_PLAYBACK_CYCLE:
        return "cycle";
    }
    return "?";
}

static void status_window(view_ui *ui)
{
    const mm_character *c = ui->character;
    const mm_database *db = c->db;
    int frame = c->frame >= 0 && c->frame < db->frame_count ? c->frame : 0;
    const mm_db_clip *clip = &db->clips[db->frame_clip[frame]];
    int in_clip = frame - clip->first_frame;
    if (ui->message && ui->message[0]) { /* the last thing done: a save, a restart, a replay's verdict */
        ImGui::TextWrapped("%s", ui->message);
        ImGui::Separator();
    }
    ImGui::Text("clip   %s", clip->name);
    ImGui::Text("frame  %d / %d   t %.2f s", in_clip, clip->frame_count,
                (double)((float)in_clip * db->interval));
    ImGui::Text("tick   %ld   (%.2f s)%s", ui->tick, (double)((float)ui->tick * ui->tick_seconds),
                ui->paused ? "   PAUSED" : "");
    const mm_input *in = ui->input;
    mm_vec3 want = mm_vec3_make(0, 0, 0);
    mm_trajectory_desired(c->trajectory, in, &want, NULL);
    float asked = std::sqrt(want.x * want.x + want.z * want.z);
    float speed = std::sqrt(c->trajectory->velocity.x * c->trajectory->velocity.x +
                            c->trajectory->velocity.z * c->trajectory->velocity.z);
    const char *gait = mm_gait_name(mm_input_gait(in));
    ImGui::Text("gait   %s%s%s%s", gait ? gait : "?", in && in->strafe ? "  strafe" : "",
                c->idle ? "  idle" : "", c->move_playing ? "  move" : "");
    ImGui::Text("speed  asked %.2f m/s   now %.2f m/s", (double)asked, (double)speed);
    ImGui::Text("play   %s  rate %.2f  stride %.2f", playback_name(c->playback), (double)c->play_rate,
                (double)c->stride_scale);
    if (c->desc.no_foot_ik)
        ImGui::TextUnformatted("feet   as animated (foot IK off)");
    else
        ImGui::Text("feet   left %s  right %s", c->foot_locked[0] ? "locked" : "free",
                    c->foot_locked[1] ? "locked" : "free");
    ImGui::Separator();
    if (ui->candidate_count > 0) { /* the winner, with every term of its cost */
        const mm_candidate *w = &ui->candidates[0];
        ImGui::Text("cost   %.4f  (base %.4f)", (double)w->cost, (double)w->base);
        ImGui::Text("  pose positions   %.4f", (double)w->terms.pose_position);
        ImGui::Text("  pose velocities  %.4f", (double)w->terms.pose_velocity);
        ImGui::Text("  root velocity    %.4f", (double)w->terms.root_velocity);
        ImGui::Text("  traj positions   %.4f", (double)w->terms.traj_position);
        ImGui::Text("  traj directions  %.4f", (double)w->terms.traj_direction);
        ImGui::Text("  loop favour      %+.4f", (double)w->loop_favour);
        ImGui::Text("  contact favour   %+.4f", (double)w->contact_favour);
        ImGui::Text("  next pose favour %+.4f", (double)w->next_pose_favour);
        ImGui::Text("  continuing bias  %+.4f", (double)w->continuing_bias);
        ImGui::Text("  ratio %.3f", (double)c->last_params.pose_trajectory_ratio);
    } else {
        ImGui::TextUnformatted("cost   - (no search yet)");
    }
    ImGui::Text("search %.0f us   searches %d", (double)c->last_search_us, c->searches);
    ImGui::Text("transitions %d  cancelled %d", c->transitions, c->cancelled_transitions);
    ImGui::Text("fps    %.0f   recording %.0f s", (double)ui->fps,
                (double)((float)(ui->last - ui->first + 1) * ui->tick_seconds));
}

static void layers_window(view_ui *ui)
{
    mm_view_layers *l = &ui->tuning->layers;
    ImGui::TextUnformatted("Runtime layers (act on the next tick)");
    int mode = l->crossfade ? 1 : 0;
    bool changed = false;
    changed |= ImGui::RadioButton("inertialization", &mode, 0);
    ImGui::SameLine();
    changed |= ImGui::RadioButton("crossfade (restarts)", &mode, 1);
    l->crossfade = mode == 1;
    changed |= ImGui::Checkbox("foot lock + leg IK  [F]", &l->foot_ik);
    changed |= ImGui::Checkbox("distance matching  [G]", &l->distance_matching);
    changed |= ImGui::Checkbox("warping  [V]", &l->warping);
    changed |= ImGui::Checkbox("root sync  [Y]", &l->root_sync);
    changed |= ImGui::Checkbox("root clamps  [U]", &l->root_clamps);
    if (changed) ui->layers_changed = true;
    ImGui::Separator();
    ImGui::TextUnformatted("Debug drawing");
    mm_view_flags *f = ui->flags;
    ImGui::Checkbox("predicted trajectory  [1]", &f->predicted);
    ImGui::Checkbox("matched trajectory  [2]", &f->matched);
    ImGui::Checkbox("past trajectory  [3]", &f->past);
    ImGui::Checkbox("foot contacts  [4]", &f->contacts);
    ImGui::Checkbox("matched bones  [5]", &f->matched_bones);
    ImGui::Checkbox("velocities  [6]", &f->velocities);
    ImGui::Checkbox("candidate ghosts  [7]", &ui->draws->ghosts);
    ImGui::Checkbox("candidate preview  [8]", &ui->draws->preview);
}

static void tuning_window(view_ui *ui)
{
    mm_view_tuning *t = ui->tuning;
    if (ui->can_save) {
        if (ImGui::Button("Save changed [F5]")) ui->save = true;
        ImGui::SameLine();
    } else {
        ImGui::TextUnformatted("(--config to save)");
        ImGui::SameLine();
    }
    if (ImGui::Button("Reset character [R]")) ui->reset = true;
    ImGui::PushItemWidth(ImGui::GetContentRegionAvail().x * 0.5f);
    for (int i = 0; i < t->count; ++i) {
        mm_view_tuning_entry *e = &t->entries[i];
        float v = mm_view_tuning_value(t, i);
        bool changed = std::fmax(*e->value, 0.0f) != std::fmax(e->saved, 0.0f);
        if (i == t->selected) ImGui::PushStyleColor(ImGuiCol_FrameBg, ImVec4(0.35f, 0.3f, 0.1f, 1.0f));
        char label[64];
        std::snprintf(label, sizeof label, "%s%s", e->name, changed ? " *" : "");
        if (ImGui::SliderFloat(label, &v, e->min, e->max, "%.4g",
                               e->multiply ? ImGuiSliderFlags_Logarithmic : ImGuiSliderFlags_None)) {
            mm_view_tuning_set(t, i, v);
            t->selected = i;
            ui->tuning_changed = true;
        }
        if (i == t->selected) ImGui::PopStyleColor();
    }
    ImGui::PopItemWidth();
}

static void candidates_window(view_ui *ui)
{
    const mm_database *db = ui->character->db;
    ImGui::TextWrapped("The search's best frames ([ ] pick, 7 ghosts, 8 preview)");
    if (ui->note) ImGui::TextWrapped("%s", ui->note);
    ImGuiTableFlags flags = ImGuiTableFlags_RowBg | ImGuiTableFlags_Borders | ImGuiTableFlags_ScrollX |
                            ImGuiTableFlags_ScrollY | ImGuiTableFlags_SizingFixedFit;
    enum { COLUMNS = 13 };
    // as tall as its rows, so that the picked frame's line shows below it
    float height = ImGui::GetFrameHeightWithSpacing() * (float)(ui->candidate_count + 1) +
                   ImGui::GetStyle().ScrollbarSize;
    if (ImGui::BeginTable("candidates", COLUMNS, flags, ImVec2(0.0f, height))) {
        // the cost and its terms first (the five weighted distances, what favours and bias add), then
        // which frame: clip names can be long
        static const char *const heads[COLUMNS] = {"#",    "cost", "pose", "vel",  "root",  "traj", "dir",
                                                   "loop", "feet", "next", "bias", "frame", "clip"};
        ImGui::TableSetupScrollFreeze(1, 1);
        for (int k = 0; k < COLUMNS; ++k) ImGui::TableSetupColumn(heads[k]);
        ImGui::TableHeadersRow();
        for (int i = 0; i < ui->candidate_count; ++i) {
            const mm_candidate *v = &ui->candidates[i];
            if (v->frame < 0 || v->clip < 0) continue;
            ImGui::TableNextRow();
            ImGui::TableSetColumnIndex(0);
            char label[16];
            std::snprintf(label, sizeof label, "%d", i);
            if (ImGui::Selectable(label, *ui->selected == i, ImGuiSelectableFlags_SpanAllColumns)) {
                *ui->selected = *ui->selected == i ? -1 : i;
                ui->select_changed = true;
            }
            const float terms[10] = {v->cost,
                                     v->terms.pose_position,
                                     v->terms.pose_velocity,
                                     v->terms.root_velocity,
                                     v->terms.traj_position,
                                     v->terms.traj_direction,
                                     v->loop_favour,
                                     v->contact_favour,
                                     v->next_pose_favour,
                                     v->continuing_bias};
            for (int k = 0; k < 10; ++k) {
                ImGui::TableSetColumnIndex(1 + k);
                ImGui::Text("%.4f", (double)terms[k]);
            }
            ImGui::TableSetColumnIndex(11);
            ImGui::Text("%d", v->frame - db->clips[v->clip].first_frame);
            ImGui::TableSetColumnIndex(12);
            ImGui::TextUnformatted(db->clips[v->clip].name);
        }
        ImGui::EndTable();
    }
    if (*ui->selected >= 0 && *ui->selected < ui->candidate_count && ui->preview_frame >= 0) {
        int f = ui->preview_frame;
        const mm_db_clip *clip = &db->clips[db->frame_clip[f]];
        const mm_candidate *v = &ui->candidates[*ui->selected];
        ImGui::TextWrapped("picked %d: %s frame %d; preview at frame %d / %d", *ui->selected,
                           db->clips[v->clip].name, v->frame - db->clips[v->clip].first_frame,
                           f - clip->first_frame, clip->frame_count);
    }
}

static void timeline_window(view_ui *ui)
{
    if (ImGui::Button("|<")) ui->seek = 0;
    ImGui::SameLine();
    if (ImGui::Button("< [,]")) ui->step_back = 1;
    ImGui::SameLine();
    if (ImGui::Button(ui->paused ? "play [space]" : "pause [space]")) ui->toggle_pause = true;
    ImGui::SameLine();
    if (ImGui::Button("[.] >")) ui->step_forward = 1;
    ImGui::SameLine();
    if (ImGui::Button(">|")) ui->seek = ui->last;
    ImGui::SameLine();
    int tick = (int)ui->tick, first = (int)ui->first, last = (int)ui->last;
    ImGui::PushItemWidth(-1.0f);
    char format[80];
    std::snprintf(format, sizeof format, "tick %%d  (%.2f s)   kept %d to %d",
                  (double)((float)ui->tick * ui->tick_seconds), first, last);
    if (ImGui::SliderInt("##tick", &tick, first, last > first ? last : first + 1, format) &&
        tick != (int)ui->tick)
        ui->seek = tick;
    ImGui::PopItemWidth();
}

void view_panel_draw(view_panel *p, view_ui *ui)
{
    ui->tuning_changed = ui->layers_changed = ui->toggle_pause = false;
    ui->step_back = ui->step_forward = 0;
    ui->save = ui->reset = ui->select_changed = false;
    ui->seek = -1;
    float scale = scale_for(p->window);
    if (scale != p->scale) build_font(p, scale);
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    ImGuiIO &io = ImGui::GetIO();
    float w = io.DisplaySize.x, h = io.DisplaySize.y;
    ImGuiCond cond = w != p->display_w || h != p->display_h ? ImGuiCond_Always : ImGuiCond_FirstUseEver;
    p->display_w = w, p->display_h = h;
    float column = w * column_fraction;
    float timeline_h = ImGui::GetFrameHeightWithSpacing() + ImGui::GetStyle().WindowPadding.y * 2.0f;
    float side_h = h - timeline_h;
    ImGuiWindowFlags flags = ImGuiWindowFlags_NoCollapse;

    place(ui, VIEW_PANEL_STATUS, 0, 0, column, side_h * 0.55f, cond);
    if (ImGui::Begin("Status", NULL, flags)) status_window(ui);
    note_rect(ui, VIEW_PANEL_STATUS);
    ImGui::End();
    place(ui, VIEW_PANEL_LAYERS, 0, side_h * 0.55f, column, side_h * 0.45f, cond);
    if (ImGui::Begin("Layers", NULL, flags)) layers_window(ui);
    note_rect(ui, VIEW_PANEL_LAYERS);
    ImGui::End();
    place(ui, VIEW_PANEL_CANDIDATES, w - column, 0, column, side_h * 0.4f, cond);
    if (ImGui::Begin("Why this pose", NULL, flags)) candidates_window(ui);
    note_rect(ui, VIEW_PANEL_CANDIDATES);
    ImGui::End();
    place(ui, VIEW_PANEL_TUNING, w - column, side_h * 0.4f, column, side_h * 0.6f, cond);
    if (ImGui::Begin("Tuning", NULL, flags)) tuning_window(ui);
    note_rect(ui, VIEW_PANEL_TUNING);
    ImGui::End();
    place(ui, VIEW_PANEL_TIMELINE, 0, side_h, w, timeline_h, cond);
    if (ImGui::Begin("Timeline", NULL, flags | ImGuiWindowFlags_NoTitleBar)) timeline_window(ui);
    note_rect(ui, VIEW_PANEL_TIMELINE);
    ImGui::End();

    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}
