/*
 * embree_instances: what a hundred thousand instances of one mesh cost Embree 3, to set beside
 * rayforge's `add: array` (docs/performance.md, "Many instances").
 *
 *   embree_instances OBJ NX NZ STEP [--threads N]
 *
 * Reads the OBJ's vertices and triangular faces (`v` and `f` lines; a face's `a/b/c` corners
 * keep their vertex index), builds it as one Embree scene, then a top-level scene of NX × NZ
 * instances of it on a grid STEP apart (the layout of bench/instances/dragons-100k.yml), each
 * an RTC_GEOMETRY_TYPE_INSTANCE with its own 3×4 transform, as an application places copies.
 * Prints ONE line of JSON: the resident set (VmRSS, from /proc/self/status) after the mesh's
 * scene is built and after the instances' scene is, their difference per instance, the peak
 * (VmHWM) and the two build times:
 *
 *   {"peer":"embree","embree_version":"3.13.5","triangles":..,"instances":..,
 *    "rss_mesh_kb":..,"rss_all_kb":..,"bytes_per_instance":..,"peak_kb":..,
 *    "mesh_build_seconds":..,"instance_build_seconds":..}
 *
 * Errors go to stderr with exit status 1 (2 for bad usage). Build (Debian's libembree-dev):
 *
 *   cc -O2 -std=c11 -o embree_instances bench/peers/embree/instances.c -lembree3 -lm
 */
#define _POSIX_C_SOURCE 200809L

#include <embree3/rtcore.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static void die(const char *what, const char *detail) {
    fprintf(stderr, "embree_instances: %s%s%s\n", what, detail ? ": " : "", detail ? detail : "");
    exit(1);
}

static double now_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* A field of /proc/self/status in kB (VmRSS, VmHWM). */
static long status_kb(const char *field) {
    FILE *f = fopen("/proc/self/status", "r");
    if (!f) die("cannot open", "/proc/self/status");
    char line[256];
    long kb = -1;
    size_t n = strlen(field);
    while (fgets(line, sizeof line, f)) {
        if (strncmp(line, field, n) == 0 && line[n] == ':') {
            kb = strtol(line + n + 1, NULL, 10);
            break;
        }
    }
    fclose(f);
    if (kb < 0) die("no such field in /proc/self/status", field);
    return kb;
}

/* A growable array of 32-bit words. */
typedef struct {
    void *data;
    size_t len, cap, size;
} Array;

static void push(Array *a, const void *item) {
    if (a->len == a->cap) {
        a->cap = a->cap ? a->cap * 2 : 1024;
        a->data = realloc(a->data, a->cap * a->size);
        if (!a->data) die("out of memory", NULL);
    }
    memcpy((char *)a->data + a->len * a->size, item, a->size);
    a->len++;
}

/* The OBJ's positions and triangles (1-based indices in the file, 0-based here; negative
 * indices count back from the last vertex). */
static void read_obj(const char *path, Array *positions, Array *triangles) {
    FILE *f = fopen(path, "r");
    if (!f) die("cannot open", path);
    char line[1024];
    while (fgets(line, sizeof line, f)) {
        if (line[0] == 'v' && line[1] == ' ') {
            float p[3];
            if (sscanf(line + 2, "%f %f %f", &p[0], &p[1], &p[2]) != 3) die("bad vertex line", line);
            push(positions, p);
        } else if (line[0] == 'f' && line[1] == ' ') {
            long idx[3];
            char *s = line + 2;
            for (int k = 0; k < 3; k++) {
                char *end;
                idx[k] = strtol(s, &end, 10);
                if (end == s) die("a face with fewer than three corners", line);
                while (*end && *end != ' ' && *end != '\t' && *end != '\n') end++;
                s = end;
            }
            uint32_t t[3];
            for (int k = 0; k < 3; k++) {
                long i = idx[k] > 0 ? idx[k] - 1 : (long)positions->len + idx[k];
                if (i < 0 || (size_t)i >= positions->len) die("a face names a missing vertex", line);
                t[k] = (uint32_t)i;
            }
            push(triangles, t);
        }
    }
    fclose(f);
    if (triangles->len == 0) die("no triangles in", path);
}

int main(int argc, char **argv) {
    if (argc < 5) {
        fprintf(stderr, "usage: embree_instances OBJ NX NZ STEP [--threads N]\n");
        return 2;
    }
    const char *obj = argv[1];
    long nx = strtol(argv[2], NULL, 10), nz = strtol(argv[3], NULL, 10);
    float step = strtof(argv[4], NULL);
    int threads = 0;
    for (int i = 5; i + 1 < argc; i += 2) {
        if (strcmp(argv[i], "--threads") == 0) threads = atoi(argv[i + 1]);
    }
    if (nx <= 0 || nz <= 0 || nx * nz > 10000000) {
        fprintf(stderr, "embree_instances: NX and NZ must be positive, NX × NZ at most 10 M\n");
        return 2;
    }

    Array positions = {.size = 3 * sizeof(float)}, triangles = {.size = 3 * sizeof(uint32_t)};
    read_obj(obj, &positions, &triangles);

    char config[64];
    snprintf(config, sizeof config, "threads=%d", threads);
    RTCDevice device = rtcNewDevice(config);
    if (!device) die("rtcNewDevice failed", NULL);

    double started = now_seconds();
    RTCScene mesh_scene = rtcNewScene(device);
    RTCGeometry mesh = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *v = rtcSetNewGeometryBuffer(mesh, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                       3 * sizeof(float), positions.len);
    uint32_t *t = rtcSetNewGeometryBuffer(mesh, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                          3 * sizeof(uint32_t), triangles.len);
    if (!v || !t) die("cannot allocate the mesh's buffers", NULL);
    memcpy(v, positions.data, positions.len * positions.size);
    memcpy(t, triangles.data, triangles.len * triangles.size);
    rtcCommitGeometry(mesh);
    rtcAttachGeometry(mesh_scene, mesh);
    rtcReleaseGeometry(mesh);
    rtcCommitScene(mesh_scene);
    double mesh_seconds = now_seconds() - started;
    /* The file's arrays are freed, as a renderer that has handed its mesh over would. */
    free(positions.data);
    free(triangles.data);
    long rss_mesh = status_kb("VmRSS");

    started = now_seconds();
    RTCScene top = rtcNewScene(device);
    for (long i = 0; i < nx; i++) {
        for (long k = 0; k < nz; k++) {
            RTCGeometry instance = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
            rtcSetGeometryInstancedScene(instance, mesh_scene);
            /* Column-major 3×4: a turn of 0.5 rad about y and a scale of 0.81, then the grid's
             * offset (dragons-100k.yml's define and array). */
            float c = 0.81f * 0.87758256f, s = 0.81f * 0.47942554f;
            float xfm[12] = {c, 0, -s, 0, 0.81f, 0, s, 0, c,
                             -480.0f + step * (float)i, 0, -480.0f + step * (float)k};
            rtcSetGeometryTransform(instance, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, xfm);
            rtcCommitGeometry(instance);
            rtcAttachGeometry(top, instance);
            rtcReleaseGeometry(instance);
        }
    }
    rtcCommitScene(top);
    double instance_seconds = now_seconds() - started;
    long rss_all = status_kb("VmRSS");
    long peak = status_kb("VmHWM");
    long count = nx * nz;

    printf("{\"peer\":\"embree\",\"embree_version\":\"%d.%d.%d\",\"triangles\":%zu,"
           "\"instances\":%ld,\"rss_mesh_kb\":%ld,\"rss_all_kb\":%ld,"
           "\"bytes_per_instance\":%.1f,\"peak_kb\":%ld,\"mesh_build_seconds\":%.4f,"
           "\"instance_build_seconds\":%.4f}\n",
           RTC_VERSION_MAJOR, RTC_VERSION_MINOR, RTC_VERSION_PATCH, triangles.len, count,
           rss_mesh, rss_all, (double)(rss_all - rss_mesh) * 1024.0 / (double)count, peak,
           mesh_seconds, instance_seconds);

    rtcReleaseScene(top);
    rtcReleaseScene(mesh_scene);
    rtcReleaseDevice(device);
    return 0;
}
