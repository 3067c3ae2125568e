/*
 * embree_primary: primary-ray throughput of Embree 3 on the mesh and rays that `rayforge bench`
 * writes, traced the way rayforge traces them, so the two times can be divided.
 *
 *   embree_primary MESH RAYS [--threads N] [--repeat R]
 *
 * MESH (little-endian): "RFMESH01", u64 vertex_count, u64 triangle_count,
 *                       vertex_count x 3 f32 positions, triangle_count x 3 u32 indices.
 * RAYS (little-endian): "RFRAYS01", u64 count, count x 6 f32 (origin xyz, direction xyz),
 *                       stored in the order to trace them (rayforge writes 8x8 screen tiles).
 *
 * The scene is built R times on a device with threads=N (the fastest rtcCommitScene is
 * reported: Embree's default
 * build, as an application that does not tune it gets). Then N pthreads take chunks of 4096
 * consecutive rays from an atomic counter and trace each with the single-ray API rtcIntersect1
 * (tnear 0, tfar +inf); this is how `rayforge bench` schedules its own side. The best of R
 * traces is reported, as ONE line of JSON on stdout:
 *
 *   {"peer":"embree","embree_version":"3.13.5","triangles":..,"rays":..,"threads":..,
 *    "build_seconds":..,"trace_seconds":..,"hits":..,"t_sum":..}
 *
 * hits and t_sum (the sum of hit distances) let rayforge check that both traced the same rays
 * through the same triangles. Errors go to stderr with exit status 1 (2 for bad usage).
 */
#define _POSIX_C_SOURCE 200809L

#include <embree3/rtcore.h>
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* Rays per chunk taken from the shared counter: large enough that the counter is not contended,
 * small enough that two threads finish within a chunk of each other. rayforge uses the same. */
#define CHUNK 4096

static void die(const char *what, const char *detail) {
    fprintf(stderr, "embree_primary: %s%s%s\n", what, detail ? ": " : "", detail ? detail : "");
    exit(1);
}

static double now_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* The file's header: an 8-byte magic, then `counts` little-endian u64s. The x86-64 hosts this
 * runs on are little-endian, so the values are read as they lie. */
static FILE *open_with_header(const char *path, const char *magic, uint64_t *counts, int n) {
    FILE *f = fopen(path, "rb");
    if (!f) die("cannot open", path);
    char found[8];
    if (fread(found, 1, 8, f) != 8 || memcmp(found, magic, 8) != 0) die("not a file of this kind (bad magic)", path);
    if (fread(counts, sizeof(uint64_t), (size_t)n, f) != (size_t)n) die("truncated header", path);
    return f;
}

static void read_exactly(FILE *f, void *into, size_t size, size_t count, const char *path) {
    if (fread(into, size, count, f) != count) die("truncated file", path);
}

struct Work {
    RTCScene scene;
    const float *rays; /* 6 floats per ray */
    uint64_t count;
    atomic_uint_fast64_t next;
    /* Per-thread results, summed after the join (no sharing while tracing). */
    uint64_t hits;
    double t_sum;
    pthread_mutex_t lock;
};

static void *trace_worker(void *arg) {
    struct Work *w = arg;
    struct RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    uint64_t hits = 0;
    double t_sum = 0.0;
    for (;;) {
        uint64_t start = atomic_fetch_add(&w->next, CHUNK);
        if (start >= w->count) break;
        uint64_t end = start + CHUNK < w->count ? start + CHUNK : w->count;
        for (uint64_t i = start; i < end; i++) {
            const float *r = w->rays + 6 * i;
            struct RTCRayHit rh;
            rh.ray.org_x = r[0];
            rh.ray.org_y = r[1];
            rh.ray.org_z = r[2];
            rh.ray.dir_x = r[3];
            rh.ray.dir_y = r[4];
            rh.ray.dir_z = r[5];
            rh.ray.tnear = 0.0f;
            rh.ray.tfar = INFINITY;
            rh.ray.time = 0.0f;
            rh.ray.mask = 0xFFFFFFFFu;
            rh.ray.id = 0;
            rh.ray.flags = 0;
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(w->scene, &context, &rh);
            if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
                hits++;
                t_sum += (double)rh.ray.tfar;
            }
        }
    }
    pthread_mutex_lock(&w->lock);
    w->hits += hits;
    w->t_sum += t_sum;
    pthread_mutex_unlock(&w->lock);
    return NULL;
}

static void usage(void) {
    fprintf(stderr, "usage: embree_primary MESH RAYS [--threads N] [--repeat R]\n");
    exit(2);
}

static long positive_arg(const char *text, const char *flag) {
    char *end = NULL;
    long v = strtol(text, &end, 10);
    if (!end || *end != '\0' || v < 1 || v > 1024) {
        fprintf(stderr, "embree_primary: %s wants a whole number from 1 to 1024, not '%s'\n", flag, text);
        exit(2);
    }
    return v;
}

int main(int argc, char **argv) {
    const char *mesh_path = NULL, *rays_path = NULL;
    long threads = 1, repeat = 1;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--threads") == 0 && i + 1 < argc) threads = positive_arg(argv[++i], "--threads");
        else if (strcmp(argv[i], "--repeat") == 0 && i + 1 < argc) repeat = positive_arg(argv[++i], "--repeat");
        else if (argv[i][0] == '-') usage();
        else if (!mesh_path) mesh_path = argv[i];
        else if (!rays_path) rays_path = argv[i];
        else usage();
    }
    if (!mesh_path || !rays_path) usage();

    /* The mesh. */
    uint64_t mesh_counts[2];
    FILE *mf = open_with_header(mesh_path, "RFMESH01", mesh_counts, 2);
    uint64_t vertex_count = mesh_counts[0], triangle_count = mesh_counts[1];
    if (vertex_count == 0 || triangle_count == 0 || vertex_count > UINT32_MAX || triangle_count > UINT32_MAX)
        die("the mesh is empty or too large for 32-bit indices", mesh_path);

    char config[64];
    snprintf(config, sizeof config, "threads=%ld", threads);
    RTCDevice device = rtcNewDevice(config);
    if (!device) die("rtcNewDevice failed", config);
    RTCScene scene = rtcNewScene(device);
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    /* Embree may read 16 bytes at the last vertex; its buffers are padded for that. */
    float *vertices = rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                              3 * sizeof(float), (size_t)vertex_count);
    unsigned *indices = rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                3 * sizeof(unsigned), (size_t)triangle_count);
    if (!vertices || !indices) die("cannot allocate the geometry buffers", NULL);
    read_exactly(mf, vertices, sizeof(float), 3 * (size_t)vertex_count, mesh_path);
    read_exactly(mf, indices, sizeof(unsigned), 3 * (size_t)triangle_count, mesh_path);
    fclose(mf);
    for (uint64_t i = 0; i < 3 * triangle_count; i++)
        if (indices[i] >= vertex_count) die("a triangle names a vertex the mesh does not have", mesh_path);
    rtcCommitGeometry(geometry);

    /* Build R times (the first build also pays for starting Embree's threads and touching
       fresh memory); keep the fastest, and the last scene for tracing. */
    double build_seconds = INFINITY;
    for (long round = 0; round < repeat; round++) {
        if (round > 0) {
            rtcReleaseScene(scene);
            scene = rtcNewScene(device);
        }
        rtcAttachGeometry(scene, geometry);
        double build_start = now_seconds();
        rtcCommitScene(scene);
        double seconds = now_seconds() - build_start;
        if (seconds < build_seconds) build_seconds = seconds;
        if (rtcGetDeviceError(device) != RTC_ERROR_NONE) die("building the scene failed", NULL);
    }
    rtcReleaseGeometry(geometry);

    /* The rays. */
    uint64_t ray_count;
    FILE *rf = open_with_header(rays_path, "RFRAYS01", &ray_count, 1);
    if (ray_count == 0 || ray_count > ((uint64_t)1 << 32)) die("no rays, or more than 2^32", rays_path);
    float *rays = malloc(sizeof(float) * 6 * (size_t)ray_count);
    if (!rays) die("out of memory for the rays", NULL);
    read_exactly(rf, rays, sizeof(float), 6 * (size_t)ray_count, rays_path);
    fclose(rf);

    /* Trace R times; keep the fastest. */
    double best = INFINITY;
    uint64_t hits = 0;
    double t_sum = 0.0;
    pthread_t *workers = malloc(sizeof(pthread_t) * (size_t)threads);
    if (!workers) die("out of memory", NULL);
    for (long round = 0; round < repeat; round++) {
        struct Work w = {.scene = scene, .rays = rays, .count = ray_count, .hits = 0, .t_sum = 0.0};
        atomic_init(&w.next, 0);
        pthread_mutex_init(&w.lock, NULL);
        double start = now_seconds();
        for (long t = 0; t < threads; t++)
            if (pthread_create(&workers[t], NULL, trace_worker, &w) != 0) die("pthread_create failed", NULL);
        for (long t = 0; t < threads; t++) pthread_join(workers[t], NULL);
        double seconds = now_seconds() - start;
        pthread_mutex_destroy(&w.lock);
        if (seconds < best) best = seconds;
        hits = w.hits;
        t_sum = w.t_sum;
    }

    printf("{\"peer\":\"embree\",\"embree_version\":\"%ld.%ld.%ld\",\"triangles\":%llu,\"rays\":%llu,"
           "\"threads\":%ld,\"build_seconds\":%.6f,\"trace_seconds\":%.6f,\"hits\":%llu,\"t_sum\":%.6f}\n",
           (long)rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_VERSION_MAJOR),
           (long)rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_VERSION_MINOR),
           (long)rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_VERSION_PATCH),
           (unsigned long long)triangle_count, (unsigned long long)ray_count, threads, build_seconds, best,
           (unsigned long long)hits, t_sum);

    free(workers);
    free(rays);
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
    return 0;
}
