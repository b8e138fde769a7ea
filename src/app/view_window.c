/* SPDX-License-Identifier: MIT
 * The interactive viewer: GLFW window, camera controls, readout in the title bar.
 *
 * Design: the main thread owns the window and the GL context. Each frame renders the
 * scene into an offscreen target (the same path as headless) and blits it to the
 * window. Mouse picking reads the target's depth under the cursor.
 */
#include "app/view_window.h"

#include <epoxy/gl.h> // before GLFW, which must not include GL headers itself
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "app/view_setup.h"
#include "core/log.h"
#include "render/bindings.h"
#include "render/camera_path.h"
#include "render/gl.h"
#include "render/scene.h"

typedef struct view_state {
    sta_scene *scene;
    sta_camera camera;
    sta_camera home; /* R resets to it */
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
    double record_start_s;
    int colour_mode;
} view_state;

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

static void look_at(sta_camera *c, const double target[3])
{
    double d[3] = { target[0] - c->position[0], target[1] - c->position[1],
                    target[2] - c->position[2] };
    double len = length3(d);
    if (len <= 0) {
        return;
    }
    c->yaw = atan2(d[1], d[0]);
    c->pitch = asin(d[2] / len);
}

static void orbit(view_state *s, double dx, double dy)
{
    sta_camera *c = &s->camera;
    double offset[3] = { c->position[0] - s->pivot[0], c->position[1] - s->pivot[1],
                         c->position[2] - s->pivot[2] };
    double radius = length3(offset);
    double yaw = atan2(offset[1], offset[0]) - dx * 0.005;
    double pitch = asin(radius > 0 ? offset[2] / radius : 0) + dy * 0.005;
    pitch = fmax(-1.5, fmin(1.5, pitch));
    c->position[0] = s->pivot[0] + radius * cos(pitch) * cos(yaw);
    c->position[1] = s->pivot[1] + radius * cos(pitch) * sin(yaw);
    c->position[2] = s->pivot[2] + radius * sin(pitch);
    look_at(c, s->pivot);
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

static void on_mouse_button(GLFWwindow *window, int button, int action, int mods)
{
    view_state *s = glfwGetWindowUserPointer(window);
    double x, y;
    glfwGetCursorPos(window, &x, &y);
    bool pressed = action == GLFW_PRESS;
    if (button == GLFW_MOUSE_BUTTON_LEFT) {
        s->dragging_left = pressed && !(mods & GLFW_MOD_SHIFT);
        s->dragging_right = pressed && (mods & GLFW_MOD_SHIFT);
        double now = glfwGetTime();
        if (pressed && now - s->last_click_s < 0.3) {
            double hit[3];
            if (pick(s, x, y, hit)) { // double-click: focus the picked point
                memcpy(s->pivot, hit, sizeof(hit));
                double d = pivot_distance(s) / 3.0;
                look_at(&s->camera, hit);
                double f[3], r[3], u[3];
                sta_camera_basis(&s->camera, f, r, u);
                for (int a = 0; a < 3; a++) {
                    s->camera.position[a] = hit[a] - f[a] * d;
                }
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
    double dx = x - s->last_x, dy = y - s->last_y;
    s->last_x = x;
    s->last_y = y;
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
    glfwGetCursorPos(window, &x, &y);
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

static void on_key(GLFWwindow *window, int key, int scancode, int action, int mods)
{
    (void)scancode;
    (void)mods;
    if (action != GLFW_PRESS) {
        return;
    }
    view_state *s = glfwGetWindowUserPointer(window);
    if (key == GLFW_KEY_ESCAPE) {
        glfwSetWindowShouldClose(window, GLFW_TRUE);
    } else if (key >= GLFW_KEY_1 && key < GLFW_KEY_1 + STA_COLOUR_MODE_COUNT) {
        s->colour_mode = key - GLFW_KEY_1;
        sta_scene_set_colour_mode(s->scene, s->colour_mode);
    } else if (key == GLFW_KEY_R) {
        int w = s->camera.width_px, h = s->camera.height_px;
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
                o->hpr_exhaustive ? "exhaustive" : "pyramid");
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

// WASD/QE flying; speed follows the distance to what the camera looks at.
static void fly(view_state *s, GLFWwindow *window, double dt)
{
    double f[3], r[3], u[3];
    sta_camera_basis(&s->camera, f, r, u);
    double speed = fmax(0.5, fmin(pivot_distance(s), s->scene_size)) * 0.8;
    if (glfwGetKey(window, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS) {
        speed *= 5.0;
    }
    double move[3] = { 0, 0, 0 };
    const struct {
        int key;
        const double *axis;
        double sign;
    } keys[] = { { GLFW_KEY_W, f, 1 },  { GLFW_KEY_S, f, -1 }, { GLFW_KEY_D, r, 1 },
                 { GLFW_KEY_A, r, -1 }, { GLFW_KEY_E, u, 1 },  { GLFW_KEY_Q, u, -1 } };
    for (size_t k = 0; k < sizeof(keys) / sizeof(keys[0]); k++) {
        if (glfwGetKey(window, keys[k].key) == GLFW_PRESS) {
            for (int a = 0; a < 3; a++) {
                move[a] += keys[k].axis[a] * keys[k].sign;
            }
        }
    }
    for (int a = 0; a < 3; a++) {
        s->camera.position[a] += move[a] * speed * dt;
        if (!s->fly) {
            s->pivot[a] += move[a] * speed * dt;
        }
    }
}

static void update_title(GLFWwindow *window, const sta_frame_stats *stats, double fps,
                         uint64_t budget)
{
    char title[256];
    snprintf(title, sizeof(title),
             "strata-view  %.0f fps  %.1f / %.1f M points  %u nodes resident, %zu loading  "
             "%.0f MiB GPU",
             fps, (double)stats->points_drawn * 1e-6, (double)budget * 1e-6, stats->nodes_resident,
             stats->loader_backlog, (double)stats->gpu_bytes / 1048576.0);
    glfwSetWindowTitle(window, title);
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
    sta_scene_options options = { .budget_points = args->budget_points,
                                  .gpu_bytes_cap = args->gpu_mem_mib << 20,
                                  .min_spacing_px = args->min_spacing_px };
    sta_camera_path playback = { 0 };
    sta_status status = sta_scene_open(args->scene, &options, &s.scene, &err);
    if (status == STA_OK && args->path_file) {
        status = sta_camera_path_load(args->path_file, &playback, &err);
    }
    if (status != STA_OK) {
        fprintf(stderr, "strata-view: %s\n", err.message);
        sta_scene_close(s.scene);
        glfwDestroyWindow(window);
        glfwTerminate();
        return 1;
    }
    s.info = sta_scene_info(s.scene);
    double frame_min[3], frame_max[3];
    sta_scene_robust_bounds(s.scene, frame_min, frame_max);
    sta_view_initial_camera(args, s.info, frame_min, frame_max, &s.camera);
    s.home = s.camera;
    s.colour_mode = sta_view_initial_colour(args, s.info);
    sta_view_pipeline_options(args, &s.pipeline);
    sta_scene_set_pipeline(s.scene, &s.pipeline);
    sta_scene_set_timing(s.scene, args->stats);
    sta_scene_set_colour_mode(s.scene, s.colour_mode);
    sta_geometry_options raster = { .raster = args->raster,
                                    .force_32bit_atomics = args->raster_32bit };
    sta_scene_set_raster(s.scene, &raster);
    for (int a = 0; a < 3; a++) {
        s.pivot[a] = 0.5 * (s.info->bounds_min[a] + s.info->bounds_max[a]);
        s.scene_size = fmax(s.scene_size, s.info->bounds_max[a] - s.info->bounds_min[a]);
    }
    glfwSetWindowUserPointer(window, &s);
    glfwSetMouseButtonCallback(window, on_mouse_button);
    glfwSetCursorPosCallback(window, on_cursor);
    glfwSetScrollCallback(window, on_scroll);
    glfwSetKeyCallback(window, on_key);

    double last = glfwGetTime(), title_time = last, start = last;
    int frames_since_title = 0, frame = 0;
    sta_frame_stats stats;
    memset(&stats, 0, sizeof(stats));
    while (!glfwWindowShouldClose(window) && status == STA_OK) {
        glfwPollEvents();
        double now = glfwGetTime();
        fly(&s, window, now - last);
        last = now;
        if (playback.count > 0) {
            sta_camera_path_sample(&playback, playback.keys[0].time_s + (now - start), &s.camera);
            if (now - start > sta_camera_path_duration(&playback)) {
                glfwSetWindowShouldClose(window, GLFW_TRUE);
            }
        }
        glfwGetFramebufferSize(window, &s.camera.width_px, &s.camera.height_px);
        if (s.camera.width_px <= 0 || s.camera.height_px <= 0) {
            continue; // minimised
        }
        status = sta_scene_render(s.scene, &s.camera, &s.target, &stats, &err);
        if (frame == 0 && sta_scene_raster_choice(s.scene)) {
            fprintf(stderr, "strata-view: %s\n", sta_scene_raster_choice(s.scene)->reason);
        }
        sta_render_target_present(&s.target);
        glfwSwapBuffers(window);
        frame++;
        frames_since_title++;
        if (now - title_time > 0.5) {
            update_title(window, &stats, frames_since_title / (now - title_time),
                         args->budget_points ? args->budget_points : STA_DEFAULT_BUDGET_POINTS);
            if (args->stats) {
                printf("%.1f fps, %" PRIu64 " points; ms: geometry %.2f",
                       frames_since_title / (now - title_time), stats.points_drawn,
                       stats.geometry_ms);
                for (int pass = 0; pass < STA_PASS_COUNT; pass++) {
                    if (stats.timing.ms[pass] > 0) {
                        printf(", %s %.2f", sta_pass_name(pass), stats.timing.ms[pass]);
                    }
                }
                printf("\n");
                fflush(stdout);
            }
            title_time = now;
            frames_since_title = 0;
        }
        if (args->max_frames && frame >= args->max_frames) {
            break;
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
    sta_render_target_release(&s.target);
    sta_scene_close(s.scene);
    glfwDestroyWindow(window);
    glfwTerminate();
    return status == STA_OK ? 0 : 1;
}
