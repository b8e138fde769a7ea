/* SPDX-License-Identifier: MIT
 * The interactive viewer: GLFW window, camera controls, readout in the title bar.
 *
 * Design: the main thread owns the window and the GL context. Each frame renders the
 * scene into an offscreen target (the same path as headless) and blits it to the
 * window. Mouse picking reads the target's depth under the cursor. Cursor positions
 * arrive in window coordinates and are scaled to framebuffer pixels (HiDPI). When
 * nothing changes (camera, size, settings) and nothing is loading, the loop waits for
 * events instead of redrawing. The navigation maths is core/navigation.h.
 */
#include "app/view_window.h"

#include <epoxy/gl.h> // before GLFW, which must not include GL headers itself
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <float.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "app/view_mirror_tool.h"
#include "app/view_setup.h"
#include "app/view_survey.h"
#include "app/view_tools.h"
#include "core/alloc.h"
#include "core/log.h"
#include "core/navigation.h"
#include "render/bindings.h"
#include "render/camera_path.h"
#include "render/gl.h"
#include "render/hud_overlay.h"
#include "render/measure_file.h"
#include "render/scene.h"

typedef struct view_state {
    sta_scene *scene;
    sta_camera camera;
    sta_camera home; /* R resets to it */
    const sta_view_args *args;
    double frame_min[3], frame_max[3]; /* the robust bounds the default view frames */
    sta_render_target target;
    const sta_strata_info *info;
    double pivot[3]; /* orbit centre, world */
    bool fly;        /* F: fly mode (mouse look) instead of orbit */
    bool dragging_left, dragging_right;
    double last_x, last_y; /* cursor, window pixels */
    double last_click_s;
    double scene_size;             /* largest extent, metres */
    sta_camera_path recorded;      /* P adds keyframes */
    sta_pipeline_options pipeline; /* M, N, H, G change it */
    sta_katz_view_options katz;    /* K turns it on and off */
    sta_point_size point_size;     /* + - and Z change it */
    sta_splat_options splats;      /* [ and ] change the scale */
    int non_splat_mode;            /* the pipeline mode O returns to */
    double record_start_s;
    int colour_mode;
    double orbit_pitch[2]; /* radians: the camera's elevation above the pivot, min and max */
    double fly_ramp;       /* 0..1: fraction of full fly speed (smooth acceleration) */
    bool animating;        /* a double-click's eased move is under way */
    sta_camera anim_from, anim_to;
    double anim_start_s;
    bool redraw;                      /* something changed that the last frame does not show */
    sta_view_tools tools;             /* picking and measuring (Ctrl+click, T, Enter, ...) */
    const char *save_json;            /* J writes the measurements here */
    const char *save_csv;             /* C exports them here */
    sta_clip clip;                    /* F1-F12, L, Shift+Ctrl+click, X change it */
    bool show_ghosts;                 /* V: mirror ghosts drawn */
    sta_view_mirror_tool mirror_tool; /* O: mark mirrors (docs/MIRRORS.md) */
    double clip_corner[3];            /* first corner of a clip box being drawn */
    bool has_clip_corner;
    sta_hud_rect *marks; /* STA_VIEW_MAX_MARKS: the measurements' markers, each frame */
} view_state;

// Cursor position in framebuffer pixels (window coordinates differ on HiDPI screens).
static void cursor_px(GLFWwindow *window, double *x, double *y)
{
    int ww, wh, fw, fh;
    glfwGetCursorPos(window, x, y);
    glfwGetWindowSize(window, &ww, &wh);
    glfwGetFramebufferSize(window, &fw, &fh);
    if (ww > 0 && wh > 0) {
        *x *= (double)fw / ww;
        *y *= (double)fh / wh;
    }
}

static double length3(const double v[3])
{
    return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

// World position of the nearest drawn point within a few pixels of the cursor.
static bool pick(view_state *s, double cursor_x, double cursor_y, double out[3])
{
    const sta_camera *c = &s->camera;
    int px = (int)cursor_x, py = (int)cursor_y;
    enum {
        R = 6
    };
    float depth[(2 * R + 1) * (2 * R + 1)];
    int x0 = px - R, y0 = c->height_px - 1 - (py + R); // GL rows count from the bottom
    if (x0 < 0 || y0 < 0 || x0 + 2 * R >= c->width_px || y0 + 2 * R >= c->height_px) {
        return false;
    }
    sta_render_target_read_depth_block(&s->target, x0, y0, 2 * R + 1, 2 * R + 1, depth);
    float best = 0.0f;
    int best_i = -1;
    for (int i = 0; i < (2 * R + 1) * (2 * R + 1); i++) {
        if (depth[i] > best) { // reverse-Z: larger is nearer
            best = depth[i];
            best_i = i;
        }
    }
    if (best_i < 0) {
        return false;
    }
    double sx = x0 + best_i % (2 * R + 1) + 0.5;
    double sy = c->height_px - (y0 + best_i / (2 * R + 1) + 0.5);
    double z = c->near_m / (double)best;
    double aspect = (double)c->width_px / c->height_px, t = tan(c->fov_y * 0.5);
    double nx = (sx / c->width_px) * 2.0 - 1.0, ny = 1.0 - (sy / c->height_px) * 2.0;
    double f[3], r[3], u[3];
    sta_camera_basis(c, f, r, u);
    for (int a = 0; a < 3; a++) {
        out[a] = c->position[a] + (f[a] + r[a] * nx * t * aspect + u[a] * ny * t) * z;
    }
    return true;
}

static void orbit(view_state *s, double dx, double dy)
{
    sta_nav_orbit(&s->camera, s->pivot, -dx * 0.005, dy * 0.005, s->orbit_pitch[0],
                  s->orbit_pitch[1]);
}

static double pivot_distance(const view_state *s)
{
    double d[3] = { s->camera.position[0] - s->pivot[0], s->camera.position[1] - s->pivot[1],
                    s->camera.position[2] - s->pivot[2] };
    double len = length3(d);
    return len > 0.01 ? len : 0.01;
}

static void pan(view_state *s, double dx, double dy)
{
    double f[3], r[3], u[3];
    sta_camera_basis(&s->camera, f, r, u);
    double metres_per_px =
        pivot_distance(s) * 2.0 * tan(s->camera.fov_y * 0.5) / s->camera.height_px;
    for (int a = 0; a < 3; a++) {
        double move = (-r[a] * dx + u[a] * dy) * metres_per_px;
        s->camera.position[a] += move;
        s->pivot[a] += move;
    }
}

// Picks the point under the cursor and hands it to the measuring tools.
static void survey_click(view_state *s, double x, double y)
{
    sta_error err = { 0 };
    sta_pick_result pick;
    bool finished = false;
    sta_status status = sta_view_pick(s->scene, &s->camera, x, y, &pick, &err);
    if (status == STA_OK && s->mirror_tool.active) {
        status = sta_view_mirror_tool_click(&s->mirror_tool, &pick, &err);
    } else if (status == STA_OK) {
        status = sta_view_tools_click(&s->tools, &pick, &finished, &err);
    }
    char line[512];
    if (status != STA_OK) {
        fprintf(stderr, "strata-view: %s\n", err.message);
        return;
    }
    sta_view_describe_pick(&pick, line, sizeof(line));
    fprintf(stderr, "pick: %s\n", line);
    if (finished) {
        const sta_measure_list *list = &s->tools.list;
        sta_view_describe_measure(&list->items[list->count - 1], line, sizeof(line));
        fprintf(stderr, "measure: %s\n", line);
    }
}

static void apply_clip(view_state *s)
{
    sta_error err = { 0 };
    if (sta_scene_set_clip(s->scene, &s->clip, &err) != STA_OK) {
        fprintf(stderr, "strata-view: %s\n", err.message);
    }
}

// Two picked points span a clip box in plan (all heights).
static void clip_click(view_state *s, double x, double y)
{
    sta_error err = { 0 };
    sta_pick_result pick;
    if (sta_view_pick(s->scene, &s->camera, x, y, &pick, &err) != STA_OK || !pick.hit) {
        return;
    }
    if (!s->has_clip_corner) {
        memcpy(s->clip_corner, pick.world, sizeof(pick.world));
        s->has_clip_corner = true;
        fprintf(stderr, "clip: first corner %.3f %.3f; Shift+Ctrl+click the second\n",
                pick.world[0], pick.world[1]);
        return;
    }
    s->has_clip_corner = false;
    s->clip.has_box = true;
    for (int a = 0; a < 2; a++) {
        s->clip.box_min[a] = fmin(s->clip_corner[a], pick.world[a]);
        s->clip.box_max[a] = fmax(s->clip_corner[a], pick.world[a]);
    }
    s->clip.box_min[2] = -DBL_MAX;
    s->clip.box_max[2] = DBL_MAX;
    fprintf(stderr, "clip box: %.3f %.3f .. %.3f %.3f (X clears)\n", s->clip.box_min[0],
            s->clip.box_min[1], s->clip.box_max[0], s->clip.box_max[1]);
    apply_clip(s);
}

// F1-F12 toggle classes 1-12, L cycles the return filter, X clears clip and filters.
static bool filter_key(view_state *s, int key)
{
    static const uint32_t returns[4] = { 0, STA_CLIP_RETURN_FIRST, STA_CLIP_RETURN_LAST,
                                         STA_CLIP_RETURN_SINGLE };
    static const char *const return_names[4] = { "all", "first", "last", "single" };
    if (key >= GLFW_KEY_F1 && key <= GLFW_KEY_F12) {
        unsigned c = (unsigned)(key - GLFW_KEY_F1) + 1;
        if (!s->clip.has_classes) {
            memset(s->clip.class_mask, 0xff, sizeof(s->clip.class_mask));
        }
        sta_clip_set_class(&s->clip, c, !sta_clip_keeps_class(&s->clip, c));
        fprintf(stderr, "class %u (%s) %s\n", c, sta_pick_class_name(c),
                sta_clip_keeps_class(&s->clip, c) ? "shown" : "hidden");
    } else if (key == GLFW_KEY_L) {
        int next = 0;
        for (int i = 0; i < 4; i++) {
            next = s->clip.return_mask == returns[i] ? (i + 1) % 4 : next;
        }
        s->clip.return_mask = returns[next];
        fprintf(stderr, "returns: %s\n", return_names[next]);
    } else if (key == GLFW_KEY_X) {
        memset(&s->clip, 0, sizeof(s->clip));
        s->has_clip_corner = false;
        fprintf(stderr, "clip and filters cleared\n");
    } else {
        return false;
    }
    apply_clip(s);
    return true;
}

// + and - step the point diameter, Z toggles the adaptive size. True when `key` was one.
static bool point_size_key(view_state *s, int key)
{
    if (key == GLFW_KEY_EQUAL || key == GLFW_KEY_KP_ADD) {
        sta_point_size_step(&s->point_size, +1);
    } else if (key == GLFW_KEY_MINUS || key == GLFW_KEY_KP_SUBTRACT) {
        sta_point_size_step(&s->point_size, -1);
    } else if (key == GLFW_KEY_Z) {
        s->point_size.mode = s->point_size.mode == STA_POINT_SIZE_ADAPTIVE
                                 ? STA_POINT_SIZE_FIXED
                                 : STA_POINT_SIZE_ADAPTIVE;
    } else {
        return false;
    }
    sta_scene_set_point_size(s->scene, &s->point_size);
    char text[64];
    sta_point_size_describe(&s->point_size, text, sizeof(text));
    bool sized = s->pipeline.mode == STA_PIPELINE_RAW || s->pipeline.mode == STA_PIPELINE_EDL;
    fprintf(stderr, "point size %s%s\n", text,
            sized ? "" : " (drawn in the raw and edl pipelines: M cycles them)");
    return true;
}

// B toggles the mirror tool; while it is on, Enter closes the outline (and saves the
// file) and Backspace undoes. True when `key` was one of these.
static bool mirror_key(view_state *s, int key)
{
    sta_error err = { 0 };
    sta_status status = STA_OK;
    sta_view_mirror_tool *t = &s->mirror_tool;
    if (key == GLFW_KEY_B) {
        t->active = !t->active;
    } else if (t->active && (key == GLFW_KEY_ENTER || key == GLFW_KEY_KP_ENTER)) {
        status = sta_view_mirror_tool_close(t, s->camera.position, &err);
    } else if (t->active && key == GLFW_KEY_BACKSPACE) {
        status = sta_view_mirror_tool_undo(t, &err);
    } else {
        return false;
    }
    char line[320];
    sta_view_mirror_tool_status(t, line, sizeof(line));
    fprintf(stderr, "%s%s\n", t->active ? "" : "(off) ", line);
    if (status != STA_OK) {
        fprintf(stderr, "strata-view: %s\n", err.message);
    }
    return true;
}

// T, Enter, Backspace, J and C: the measuring tools' keys. True when `key` was one.
static bool survey_key(view_state *s, int key)
{
    sta_error err = { 0 };
    sta_status status = STA_OK;
    if (key == GLFW_KEY_T) {
        sta_view_tools_next(&s->tools);
    } else if (key == GLFW_KEY_ENTER || key == GLFW_KEY_KP_ENTER) {
        sta_view_tools_finish(&s->tools);
    } else if (key == GLFW_KEY_BACKSPACE) {
        sta_view_tools_undo(&s->tools);
    } else if (key == GLFW_KEY_J) {
        status = sta_measure_save_json(s->save_json, &s->tools.list, &err);
        fprintf(stderr, "wrote %zu measurements to %s\n", s->tools.list.count, s->save_json);
    } else if (key == GLFW_KEY_C) {
        status = sta_measure_save_csv(s->save_csv, &s->tools.list, &err);
        fprintf(stderr, "wrote %zu measurements to %s\n", s->tools.list.count, s->save_csv);
    } else {
        return false;
    }
    if (status != STA_OK) {
        fprintf(stderr, "strata-view: %s\n", err.message);
    }
    return true;
}

static void on_mouse_button(GLFWwindow *window, int button, int action, int mods)
{
    view_state *s = glfwGetWindowUserPointer(window);
    double x, y;
    cursor_px(window, &x, &y);
    bool pressed = action == GLFW_PRESS;
    s->redraw = true;
    if (button == GLFW_MOUSE_BUTTON_LEFT && pressed && (mods & GLFW_MOD_CONTROL) &&
        (mods & GLFW_MOD_SHIFT)) {
        clip_click(s, x, y); // Shift+Ctrl+click: corners of a clip box
    } else if (button == GLFW_MOUSE_BUTTON_LEFT && pressed && (mods & GLFW_MOD_CONTROL)) {
        survey_click(s, x, y); // Ctrl+click: pick and measure, no camera move
    } else if (button == GLFW_MOUSE_BUTTON_LEFT) {
        s->dragging_left = pressed && !(mods & GLFW_MOD_SHIFT);
        s->dragging_right = pressed && (mods & GLFW_MOD_SHIFT);
        double now = glfwGetTime();
        if (pressed && now - s->last_click_s < 0.3) {
            double hit[3];
            if (pick(s, x, y, hit)) { // double-click: centre the point, move closer, eased
                memcpy(s->pivot, hit, sizeof(hit));
                s->anim_from = s->camera;
                sta_nav_focus(&s->camera, hit, 1.0 / 3.0, &s->anim_to);
                s->anim_start_s = now;
                s->animating = true;
            }
        } else if (pressed && !s->fly) {
            double hit[3];
            if (pick(s, x, y, hit)) { // orbit around what is under the cursor
                memcpy(s->pivot, hit, sizeof(hit));
            }
        }
        s->last_click_s = pressed ? now : s->last_click_s;
    } else if (button == GLFW_MOUSE_BUTTON_RIGHT) {
        s->dragging_right = pressed;
    }
    s->last_x = x;
    s->last_y = y;
}

static void on_cursor(GLFWwindow *window, double x, double y)
{
    view_state *s = glfwGetWindowUserPointer(window);
    cursor_px(window, &x, &y);
    double dx = x - s->last_x, dy = y - s->last_y;
    s->last_x = x;
    s->last_y = y;
    if (s->dragging_left || s->dragging_right) {
        s->animating = false; // the user takes over
        s->redraw = true;
    }
    if (s->dragging_left && s->fly) {
        s->camera.yaw -= dx * 0.003;
        s->camera.pitch = fmax(-1.55, fmin(1.55, s->camera.pitch - dy * 0.003));
    } else if (s->dragging_left) {
        orbit(s, dx, dy);
    } else if (s->dragging_right) {
        pan(s, dx, dy);
    }
}

static void on_scroll(GLFWwindow *window, double dx, double dy)
{
    (void)dx;
    view_state *s = glfwGetWindowUserPointer(window);
    double hit[3];
    double x, y;
    cursor_px(window, &x, &y);
    s->animating = false;
    s->redraw = true;
    if (!pick(s, x, y, hit)) {
        memcpy(hit, s->pivot, sizeof(hit));
    }
    // Move a fraction of the way towards the point under the cursor.
    double fraction = dy > 0 ? 0.2 : -0.25;
    for (int a = 0; a < 3; a++) {
        s->camera.position[a] += (hit[a] - s->camera.position[a]) * fraction;
    }
    memcpy(s->pivot, hit, sizeof(hit));
}

// O: splats on and off (back to the last other mode); [ and ]: the splat radius factor.
static void splat_key(view_state *s, int key)
{
    if (key == GLFW_KEY_O) {
        if (s->pipeline.mode == STA_PIPELINE_SPLATS) {
            s->pipeline.mode = s->non_splat_mode;
        } else {
            s->non_splat_mode = s->pipeline.mode;
            s->pipeline.mode = STA_PIPELINE_SPLATS;
        }
        sta_scene_set_pipeline(s->scene, &s->pipeline);
        fprintf(stderr, "pipeline %s\n", sta_pipeline_mode_name(s->pipeline.mode));
        return;
    }
    float factor = key == GLFW_KEY_RIGHT_BRACKET ? STA_VIEW_SPLAT_SCALE_STEP
                                                 : 1.0f / STA_VIEW_SPLAT_SCALE_STEP;
    s->splats.scale *= factor;
    sta_scene_set_splats(s->scene, &s->splats);
    fprintf(stderr, "splat scale %.3g\n", (double)s->splats.scale);
}

// The initial camera (the arguments' or the default view) for a w x h framebuffer, as
// s->home; `why` as sta_view_initial_camera's.
static void frame_default_view(view_state *s, int w, int h, char *why, size_t why_size)
{
    sta_view_args sized = *s->args;
    sized.width_px = w > 0 ? w : s->args->width_px;
    sized.height_px = h > 0 ? h : s->args->height_px;
    sta_view_initial_camera(&sized, s->info, s->frame_min, s->frame_max, &s->home, why, why_size);
}

static void on_key(GLFWwindow *window, int key, int scancode, int action, int mods)
{
    (void)scancode;
    (void)mods;
    if (action != GLFW_PRESS) {
        return;
    }
    view_state *s = glfwGetWindowUserPointer(window);
    s->redraw = true;
    if (mirror_key(s, key) || survey_key(s, key) || filter_key(s, key) || point_size_key(s, key)) {
        return;
    }
    if (key == GLFW_KEY_ESCAPE) {
        glfwSetWindowShouldClose(window, GLFW_TRUE);
    } else if (key >= GLFW_KEY_1 && key < GLFW_KEY_1 + STA_COLOUR_MODE_COUNT) {
        s->colour_mode = key - GLFW_KEY_1;
        sta_scene_set_colour_mode(s->scene, s->colour_mode);
    } else if (key == GLFW_KEY_R) {
        s->animating = false;
        int w = s->camera.width_px, h = s->camera.height_px;
        if (!s->args->has_camera && (w != s->home.width_px || h != s->home.height_px)) {
            // The window changed size since the default view was framed: frame it again
            // for this one (its edges and the border margin are in pixels).
            frame_default_view(s, w, h, NULL, 0);
        }
        s->camera = s->home;
        s->camera.width_px = w;
        s->camera.height_px = h;
        for (int a = 0; a < 3; a++) {
            s->pivot[a] = 0.5 * (s->info->bounds_min[a] + s->info->bounds_max[a]);
        }
    } else if (key == GLFW_KEY_F) {
        s->fly = !s->fly;
    } else if (key == GLFW_KEY_M || key == GLFW_KEY_N || key == GLFW_KEY_H || key == GLFW_KEY_G) {
        sta_pipeline_options *o = &s->pipeline;
        if (key == GLFW_KEY_M) {
            o->mode = (o->mode + 1) % STA_PIPELINE_MODE_COUNT;
        } else if (key == GLFW_KEY_N) {
            o->normals = (o->normals + 1) % STA_NORMAL_METHOD_COUNT;
        } else if (key == GLFW_KEY_H) {
            o->hpr_exhaustive = !o->hpr_exhaustive;
        } else {
            o->smooth = !o->smooth;
        }
        sta_scene_set_pipeline(s->scene, o);
        fprintf(stderr, "pipeline %s, normals %s%s, hpr %s\n", sta_pipeline_mode_name(o->mode),
                sta_normal_method_name(o->normals), o->smooth ? " smoothed" : "",
                o->hpr_exhaustive ? "exhaustive" : (o->hpr_every_pixel ? "pyramid" : "sparse"));
    } else if (key == GLFW_KEY_V) {
        s->show_ghosts = !s->show_ghosts;
        sta_scene_set_hide_flags(s->scene, s->show_ghosts ? 0u : STA_SCENE_DEFAULT_HIDE_FLAGS);
        fprintf(stderr, "mirror ghosts %s\n", s->show_ghosts ? "shown" : "hidden");
    } else if (key == GLFW_KEY_O || key == GLFW_KEY_LEFT_BRACKET || key == GLFW_KEY_RIGHT_BRACKET) {
        splat_key(s, key);
    } else if (key == GLFW_KEY_K) {
        s->katz.enabled = !s->katz.enabled;
        sta_scene_set_katz(s->scene, &s->katz);
        fprintf(stderr, "live katz hpr %s\n", s->katz.enabled ? "on" : "off");
    } else if (key == GLFW_KEY_P) {
        sta_error err = { 0 };
        double t = glfwGetTime() - s->record_start_s;
        if (s->recorded.count == 0) {
            s->record_start_s = glfwGetTime();
            t = 0.0;
        }
        if (sta_camera_path_add(&s->recorded, &s->camera, t, &err) == STA_OK) {
            fprintf(stderr, "keyframe %zu at %.2f s\n", s->recorded.count, t);
        }
    }
}

// WASD/QE flying: speed from the distance to the surface at the centre of the screen
// (or to the orbit centre when nothing is drawn there), ramped up smoothly. Returns
// whether a fly key is held.
static bool fly(view_state *s, GLFWwindow *window, double dt)
{
    double f[3], r[3], u[3];
    sta_camera_basis(&s->camera, f, r, u);
    double move[3] = { 0, 0, 0 };
    bool moving = false;
    const struct {
        int key;
        const double *axis;
        double sign;
    } keys[] = { { GLFW_KEY_W, f, 1 },  { GLFW_KEY_S, f, -1 }, { GLFW_KEY_D, r, 1 },
                 { GLFW_KEY_A, r, -1 }, { GLFW_KEY_E, u, 1 },  { GLFW_KEY_Q, u, -1 } };
    for (size_t k = 0; k < sizeof(keys) / sizeof(keys[0]); k++) {
        if (glfwGetKey(window, keys[k].key) == GLFW_PRESS) {
            moving = true;
            for (int a = 0; a < 3; a++) {
                move[a] += keys[k].axis[a] * keys[k].sign;
            }
        }
    }
    s->fly_ramp = sta_nav_ramp(s->fly_ramp, moving, dt);
    if (!moving) {
        return false;
    }
    s->animating = false;
    double surface[3], distance = fmin(pivot_distance(s), s->scene_size);
    if (pick(s, 0.5 * s->camera.width_px, 0.5 * s->camera.height_px, surface)) {
        double d[3] = { surface[0] - s->camera.position[0], surface[1] - s->camera.position[1],
                        surface[2] - s->camera.position[2] };
        distance = length3(d);
    }
    double speed = sta_nav_fly_speed(distance, s->scene_size) * s->fly_ramp;
    if (glfwGetKey(window, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS) {
        speed *= 5.0;
    }
    for (int a = 0; a < 3; a++) {
        s->camera.position[a] += move[a] * speed * dt;
        if (!s->fly) {
            s->pivot[a] += move[a] * speed * dt;
        }
    }
    return true;
}

static void update_title(GLFWwindow *window, const sta_frame_stats *stats, double fps,
                         uint64_t budget, const view_state *s)
{
    char title[320], label[96];
    sta_view_pipeline_label(s->pipeline.mode, &s->point_size, s->splats.scale, label,
                            sizeof(label));
    snprintf(title, sizeof(title),
             "strata-view  [%s]  [%s]  %.0f fps  %.1f / %.1f M points  %u nodes resident, %zu "
             "loading  %.0f MiB GPU",
             s->fly ? "fly: WASD QE, drag to look" : "orbit", label, fps,
             (double)stats->points_drawn * 1e-6, (double)budget * 1e-6, stats->nodes_resident,
             stats->loader_backlog, (double)stats->gpu_bytes / 1048576.0);
    if (stats->katz.generation > 0) {
        size_t used = strlen(title);
        snprintf(title + used, sizeof(title) - used,
                 "  katz %" PRIu64 "/%" PRIu64 " visible, %" PRIu64 " frames old",
                 stats->katz.visible, stats->katz.points, stats->katz.age_frames);
    }
    glfwSetWindowTitle(window, title);
}

// The readout over the frame: figures, pick, measurements, the tool's hint.
static void draw_readout(view_state *s, sta_hud_overlay *hud, const sta_frame_stats *stats,
                         double fps, const sta_view_args *args, sta_error *err)
{
    sta_view_readout readout;
    uint64_t budget = args->budget_points ? args->budget_points : STA_DEFAULT_BUDGET_POINTS;
    char label[96];
    sta_view_pipeline_label(s->pipeline.mode, &s->point_size, s->splats.scale, label,
                            sizeof(label));
    sta_view_readout_fill(&readout, stats, fps, budget, label,
                          s->tools.has_pick ? &s->tools.last_pick : NULL, &s->tools.list);
    const sta_view_mirror_tool *mt = &s->mirror_tool;
    if (readout.count < STA_VIEW_HUD_MAX_LINES) {
        if (mt->active) {
            sta_view_mirror_tool_status(mt, readout.lines[readout.count], sizeof(readout.lines[0]));
        } else {
            sta_view_tools_status(&s->tools, readout.lines[readout.count],
                                  sizeof(readout.lines[0]));
        }
        readout.count++;
    }
    readout.mark_count = sta_view_measure_marks(
        &s->camera, &s->tools.list,
        mt->active ? (const double(*)[3])mt->pending : (const double(*)[3])s->tools.pending,
        mt->active ? mt->pending_count : s->tools.pending_count, s->marks, STA_VIEW_MAX_MARKS);
    sta_hud_overlay_fill_rects(s->marks, readout.mark_count, s->camera.height_px);
    const char *lines[STA_VIEW_HUD_MAX_LINES];
    sta_view_readout_pointers(&readout, lines);
    if (sta_hud_overlay_draw(hud, lines, readout.count, s->camera.width_px, s->camera.height_px,
                             err) != STA_OK) {
        fprintf(stderr, "strata-view: %s\n", err->message);
    }
}

static void on_glfw_error(int code, const char *message)
{
    fprintf(stderr, "strata-view: GLFW error 0x%x: %s\n", code, message);
}

int sta_view_run_window(const sta_view_args *args)
{
    glfwSetErrorCallback(on_glfw_error);
    if (!glfwInit()) {
        fprintf(stderr, "strata-view: cannot open a window (no display?); use --headless "
                        "--out FILE.png to render without one\n");
        return 1;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    GLFWwindow *window =
        glfwCreateWindow(args->width_px, args->height_px, "strata-view", NULL, NULL);
    if (!window) {
        glfwTerminate();
        fprintf(stderr, "strata-view: cannot create an OpenGL 4.5 window\n");
        return 1;
    }
    glfwMakeContextCurrent(window);
    glfwSwapInterval(1);

    view_state s;
    memset(&s, 0, sizeof(s));
    sta_error err = { 0 };
    sta_camera_path playback = { 0 };
    sta_mirror_set mirrors = { 0 };
    sta_status status = sta_view_open_scene(args, &mirrors, &s.scene, &err);
    if (status == STA_OK && args->path_file) {
        status = sta_camera_path_load(args->path_file, &playback, &err);
        if (status == STA_OK && args->path_speed_mps > 0) {
            status = sta_camera_path_set_speed(&playback, args->path_speed_mps, &err);
        }
    }
    if (status != STA_OK) {
        fprintf(stderr, "strata-view: %s\n", err.message);
        sta_scene_close(s.scene);
        sta_mirror_set_release(&mirrors);
        glfwDestroyWindow(window);
        glfwTerminate();
        return 1;
    }
    s.info = sta_scene_info(s.scene);
    s.args = args;
    sta_scene_robust_bounds(s.scene, s.frame_min, s.frame_max);
    // Framed for the framebuffer (larger than the window on HiDPI screens).
    int framebuffer_w = 0, framebuffer_h = 0;
    glfwGetFramebufferSize(window, &framebuffer_w, &framebuffer_h);
    char default_view[256];
    frame_default_view(&s, framebuffer_w, framebuffer_h, default_view, sizeof(default_view));
    if (default_view[0]) {
        char option[256];
        sta_view_camera_option(&s.home, option, sizeof(option));
        fprintf(stderr, "default view: %s\ndefault camera: %s\n", default_view, option);
    }
    s.camera = s.home;
    s.colour_mode = sta_view_initial_colour(args, s.info);
    sta_view_pipeline_options(args, &s.pipeline);
    sta_scene_set_pipeline(s.scene, &s.pipeline);
    sta_view_splat_options(args, &s.splats);
    sta_scene_set_splats(s.scene, &s.splats);
    s.non_splat_mode = args->pipeline == STA_PIPELINE_SPLATS ? STA_PIPELINE_SHADED : args->pipeline;
    s.katz = args->katz;
    s.show_ghosts = args->show_ghosts;
    sta_scene_set_katz(s.scene, &s.katz);
    sta_scene_set_timing(s.scene, args->stats);
    sta_scene_set_timing_clock(s.scene, args->stats_clock);
    sta_scene_set_colour_mode(s.scene, s.colour_mode);
    sta_scene_set_ramps(s.scene, args->elevation_range[0], args->elevation_range[1],
                        args->intensity_max);
    sta_geometry_options raster = { .raster = args->raster,
                                    .force_32bit_atomics = args->raster_32bit };
    sta_scene_set_raster(s.scene, &raster);
    s.point_size = args->point_size;
    sta_scene_set_point_size(s.scene, &s.point_size);
    s.orbit_pitch[0] = args->orbit_pitch_deg[0] * M_PI / 180.0;
    s.orbit_pitch[1] = args->orbit_pitch_deg[1] * M_PI / 180.0;
    for (int a = 0; a < 3; a++) {
        s.pivot[a] = 0.5 * (s.info->bounds_min[a] + s.info->bounds_max[a]);
        s.scene_size = fmax(s.scene_size, s.info->bounds_max[a] - s.info->bounds_min[a]);
    }
    sta_view_tools_init(&s.tools);
    if (sta_view_mirror_tool_init(&s.mirror_tool, args->mirrors_file, &err) != STA_OK) {
        fprintf(stderr, "strata-view: %s\n", err.message);
    }
    s.clip = args->clip;
    s.save_json = args->measure_file ? args->measure_file : "measurements.json";
    s.save_csv = args->measure_csv ? args->measure_csv : "measurements.csv";
    if (args->measure_file && access(args->measure_file, F_OK) == 0 &&
        sta_measure_load_json(args->measure_file, &s.tools.list, &err) != STA_OK) {
        fprintf(stderr, "strata-view: %s\n", err.message);
    }
    sta_hud_overlay hud = { 0 };
    s.marks = sta_alloc_array(STA_VIEW_MAX_MARKS, sizeof(*s.marks));
    bool has_hud = !args->no_readout && s.marks && sta_hud_overlay_init(&hud, &err) == STA_OK;
    if (!has_hud && !args->no_readout) {
        fprintf(stderr, "strata-view: no on-screen readout: %s\n", err.message);
    }
    double fps = 0.0;
    glfwSetWindowUserPointer(window, &s);
    glfwSetMouseButtonCallback(window, on_mouse_button);
    glfwSetCursorPosCallback(window, on_cursor);
    glfwSetScrollCallback(window, on_scroll);
    glfwSetKeyCallback(window, on_key);

    double last = glfwGetTime(), title_time = last, start = last;
    int frames_since_title = 0, frame = 0;
    sta_frame_stats stats;
    memset(&stats, 0, sizeof(stats));
    bool idle = false;
    sta_camera shown; // the camera of the last frame drawn
    memset(&shown, 0, sizeof(shown));
    while (!glfwWindowShouldClose(window) && status == STA_OK) {
        if (idle) {
            glfwWaitEventsTimeout(0.5); // nothing to redraw: sleep until input (or 0.5 s)
        } else {
            glfwPollEvents();
        }
        double now = glfwGetTime();
        bool moving = fly(&s, window, now - last);
        last = now;
        if (s.animating) {
            double t = (now - s.anim_start_s) / STA_NAV_FOCUS_SECONDS;
            sta_nav_blend(&s.anim_from, &s.anim_to, t, &s.camera);
            s.animating = t < 1.0;
        }
        if (playback.count > 0) {
            sta_camera_path_sample(&playback, playback.keys[0].time_s + (now - start), &s.camera);
            if (now - start > sta_camera_path_duration(&playback)) {
                glfwSetWindowShouldClose(window, GLFW_TRUE);
            }
        }
        glfwGetFramebufferSize(window, &s.camera.width_px, &s.camera.height_px);
        if (s.camera.width_px <= 0 || s.camera.height_px <= 0) {
            idle = true;
            continue; // minimised
        }
        // Idle: the last frame was complete and showed this camera at this size.
        bool changed = s.redraw || moving || s.animating || playback.count > 0 ||
                       memcmp(&shown, &s.camera, sizeof(shown)) != 0;
        bool was_idle = idle;
        idle = !changed && frame > 0 && stats.complete && stats.uploads == 0 && !args->max_frames;
        if (idle) {
            continue;
        }
        if (was_idle) { // frames per second count from here, not from before the pause
            title_time = now;
            frames_since_title = 0;
        }
        s.redraw = false;
        shown = s.camera;
        bool was_complete = frame > 0 && stats.complete;
        status = sta_scene_render(s.scene, &s.camera, &s.target, &stats, &err);
        if (frame == 0 && sta_scene_raster_choice(s.scene)) {
            fprintf(stderr, "strata-view: %s\n", sta_scene_raster_choice(s.scene)->reason);
        }
        sta_render_target_present(&s.target);
        if (has_hud && status == STA_OK) {
            draw_readout(&s, &hud, &stats, fps, args, &err);
        }
        glfwSwapBuffers(window);
        frame++;
        frames_since_title++;
        double drawn_s = glfwGetTime() - title_time;
        // Also when the view has just become complete: the viewer may go idle next, and
        // the title should show the last frame (e.g. the live Katz set that arrived).
        if (drawn_s > 0.5 || was_idle || (stats.complete && !was_complete)) {
            fps = frames_since_title / drawn_s;
            update_title(window, &stats, frames_since_title / drawn_s,
                         args->budget_points ? args->budget_points : STA_DEFAULT_BUDGET_POINTS, &s);
            if (args->stats) {
                printf("%.1f fps, %" PRIu64 " points; ms: geometry %.2f",
                       frames_since_title / drawn_s, stats.points_drawn, stats.geometry_ms);
                for (int pass = 0; pass < STA_PASS_COUNT; pass++) {
                    if (stats.timing.ms[pass] > 0) {
                        printf(", %s %.2f", sta_pass_name(pass), stats.timing.ms[pass]);
                    }
                }
                printf("\n");
                fflush(stdout);
            }
            if (drawn_s > 0.5) {
                title_time = glfwGetTime();
                frames_since_title = 0;
            }
        }
        if (args->max_frames && frame >= args->max_frames) {
            break;
        }
        if (s.katz.enabled && !changed && !stats.katz.current) {
            glfwWaitEventsTimeout(0.01); // only the live Katz set is awaited: leave the CPU to it
        }
    }
    if (status != STA_OK) {
        fprintf(stderr, "strata-view: %s\n", err.message);
    }
    if (args->record_file && s.recorded.count > 0) {
        if (sta_camera_path_save(args->record_file, &s.recorded, &err) != STA_OK) {
            fprintf(stderr, "strata-view: %s\n", err.message);
            status = err.code;
        } else {
            fprintf(stderr, "wrote %zu keyframes to %s\n", s.recorded.count, args->record_file);
        }
    }
    sta_camera_path_release(&s.recorded);
    sta_camera_path_release(&playback);
    sta_hud_overlay_release(&hud);
    sta_free(s.marks);
    sta_view_tools_release(&s.tools);
    sta_view_mirror_tool_release(&s.mirror_tool);
    sta_render_target_release(&s.target);
    sta_scene_close(s.scene);
    sta_mirror_set_release(&mirrors);
    glfwDestroyWindow(window);
    glfwTerminate();
    return status == STA_OK ? 0 : 1;
}
