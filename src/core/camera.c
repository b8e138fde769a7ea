/* SPDX-License-Identifier: MIT
 * Camera maths. */
#include "core/camera.h"

#include <math.h>
#include <string.h>

void sta_camera_to_frame(const sta_camera *c, const double world[3], double out[3])
{
    double x = world[0], y = world[1], z = world[2];
    if (c->up_axis == STA_CAMERA_UP_Y) {
        out[0] = x, out[1] = -z, out[2] = y;
    } else {
        out[0] = x, out[1] = y, out[2] = z;
    }
}

void sta_camera_from_frame(const sta_camera *c, const double frame[3], double out[3])
{
    double x = frame[0], y = frame[1], z = frame[2];
    if (c->up_axis == STA_CAMERA_UP_Y) {
        out[0] = x, out[1] = z, out[2] = -y;
    } else {
        out[0] = x, out[1] = y, out[2] = z;
    }
}

void sta_camera_basis(const sta_camera *c, double forward[3], double right[3], double up[3])
{
    double cp = cos(c->pitch), sp = sin(c->pitch);
    double cy = cos(c->yaw), sy = sin(c->yaw);
    forward[0] = cp * cy;
    forward[1] = cp * sy;
    forward[2] = sp;
    // right = forward x Z, normalised (horizontal).
    right[0] = sy;
    right[1] = -cy;
    right[2] = 0.0;
    // up = right x forward
    up[0] = right[1] * forward[2] - right[2] * forward[1];
    up[1] = right[2] * forward[0] - right[0] * forward[2];
    up[2] = right[0] * forward[1] - right[1] * forward[0];
    if (c->up_axis == STA_CAMERA_UP_Y) {
        double f[3] = { forward[0], forward[1], forward[2] },
               r[3] = { right[0], right[1], right[2] }, u[3] = { up[0], up[1], up[2] };
        sta_camera_from_frame(c, f, forward);
        sta_camera_from_frame(c, r, right);
        sta_camera_from_frame(c, u, up);
    }
}

void sta_camera_view_rotation(const sta_camera *c, float out[16])
{
    double f[3], r[3], u[3];
    sta_camera_basis(c, f, r, u);
    // Rows: right, up, -forward (camera looks down -Z).
    memset(out, 0, 16 * sizeof(float));
    for (int i = 0; i < 3; i++) {
        out[i * 4 + 0] = (float)r[i];
        out[i * 4 + 1] = (float)u[i];
        out[i * 4 + 2] = (float)-f[i];
    }
    out[15] = 1.0f;
}

void sta_camera_projection(const sta_camera *c, float out[16])
{
    double aspect = (double)c->width_px / (double)(c->height_px > 0 ? c->height_px : 1);
    double f = 1.0 / tan(c->fov_y * 0.5);
    memset(out, 0, 16 * sizeof(float));
    out[0] = (float)(f / aspect);
    out[5] = (float)f;
    // clip.z = near, clip.w = -z_eye: depth = near / -z_eye (1 at near, 0 at infinity).
    out[11] = -1.0f;
    out[14] = (float)c->near_m;
}

bool sta_camera_project(const sta_camera *c, const double world[3], double *out_x_px,
                        double *out_y_px, double *out_depth_m)
{
    double f[3], r[3], u[3];
    sta_camera_basis(c, f, r, u);
    double d[3] = { world[0] - c->position[0], world[1] - c->position[1],
                    world[2] - c->position[2] };
    double x = d[0] * r[0] + d[1] * r[1] + d[2] * r[2];
    double y = d[0] * u[0] + d[1] * u[1] + d[2] * u[2];
    double z = d[0] * f[0] + d[1] * f[1] + d[2] * f[2];
    *out_depth_m = z;
    if (z < c->near_m) {
        return false;
    }
    double aspect = (double)c->width_px / (double)(c->height_px > 0 ? c->height_px : 1);
    double t = tan(c->fov_y * 0.5);
    double ndc_x = x / (z * t * aspect);
    double ndc_y = y / (z * t);
    *out_x_px = (ndc_x * 0.5 + 0.5) * c->width_px;
    *out_y_px = (0.5 - ndc_y * 0.5) * c->height_px;
    return true;
}

static void plane_from(double plane[4], const double normal[3], const double point[3])
{
    double len = sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
    for (int i = 0; i < 3; i++) {
        plane[i] = normal[i] / len;
    }
    plane[3] = -(plane[0] * point[0] + plane[1] * point[1] + plane[2] * point[2]);
}

void sta_camera_frustum(const sta_camera *c, double far_m, sta_frustum *frustum)
{
    double(*out)[4] = frustum->planes;
    double f[3], r[3], u[3];
    sta_camera_basis(c, f, r, u);
    double aspect = (double)c->width_px / (double)(c->height_px > 0 ? c->height_px : 1);
    double ty = tan(c->fov_y * 0.5), tx = ty * aspect;
    const double *p = c->position;
    double n[3], point[3];
    for (int i = 0; i < 3; i++) {
        n[i] = f[i];
        point[i] = p[i] + f[i] * c->near_m;
    }
    plane_from(out[0], n, point); // near
    for (int i = 0; i < 3; i++) {
        n[i] = -f[i];
        point[i] = p[i] + f[i] * far_m;
    }
    plane_from(out[1], n, point); // far
    // Side planes pass through the eye; inward normals.
    for (int i = 0; i < 3; i++) {
        n[i] = f[i] * tx + r[i]; // left: points right-forward
    }
    plane_from(out[2], n, p);
    for (int i = 0; i < 3; i++) {
        n[i] = f[i] * tx - r[i]; // right
    }
    plane_from(out[3], n, p);
    for (int i = 0; i < 3; i++) {
        n[i] = f[i] * ty + u[i]; // bottom
    }
    plane_from(out[4], n, p);
    for (int i = 0; i < 3; i++) {
        n[i] = f[i] * ty - u[i]; // top
    }
    plane_from(out[5], n, p);
}

double sta_camera_pixels_per_metre(const sta_camera *c, double distance_m)
{
    double d = distance_m > c->near_m ? distance_m : c->near_m;
    return (double)c->height_px / (2.0 * tan(c->fov_y * 0.5) * d);
}

void sta_camera_frame_box(sta_camera *c, const double min[3], const double max[3])
{
    // Distance along the view direction at which all eight corners are inside the
    // frustum (a tight fit, unlike a bounding sphere).
    double centre[3];
    for (int i = 0; i < 3; i++) {
        centre[i] = 0.5 * (min[i] + max[i]);
    }
    double f[3], r[3], u[3];
    sta_camera_basis(c, f, r, u);
    double aspect = (double)c->width_px / (double)(c->height_px > 0 ? c->height_px : 1);
    double tan_y = tan(c->fov_y * 0.5), tan_x = tan_y * aspect;
    double distance = 1e-3;
    double extent = 0.0;
    for (int corner = 0; corner < 8; corner++) {
        double d[3];
        for (int i = 0; i < 3; i++) {
            d[i] = ((corner >> i) & 1 ? max[i] : min[i]) - centre[i];
            extent = fmax(extent, fabs(d[i]));
        }
        double x = d[0] * r[0] + d[1] * r[1] + d[2] * r[2];
        double y = d[0] * u[0] + d[1] * u[1] + d[2] * u[2];
        double z = d[0] * f[0] + d[1] * f[1] + d[2] * f[2];
        distance = fmax(distance, fabs(x) / tan_x - z);
        distance = fmax(distance, fabs(y) / tan_y - z);
    }
    distance *= 1.05; // a small margin
    for (int i = 0; i < 3; i++) {
        c->position[i] = centre[i] - f[i] * distance;
    }
    c->near_m = fmax(1e-3, fmin(distance * 1e-3, extent * 1e-3));
}
