/*
 * llvmpipe peer for rayforge's rasterizer benchmark (`raster_million -- phong`).
 *
 * Renders, with Mesa's llvmpipe software rasterizer through OSMesa (off-screen, OpenGL 3.3
 * core), the frame of crates/rayforge/benches/support/height_field.rs: the 708 x 708 quad
 * height field (1 002 528 triangles) at 1920x1080, the book's camera (fov 1.0 rad across
 * the longer side), per-pixel Phong lighting with the book's `lighting` and two point lights,
 * no shadows, depth buffer, no culling, normals turned towards the eye (as rayforge does).
 *
 * What it measures: the mesh is uploaded once (VBO + IBO); then each frame is
 * clear + draw + glFinish, timed with CLOCK_MONOTONIC. Prints the first frame, the mean of
 * all frames (as raster_million does), the mean without the first, and the best, in ms.
 * The last frame is written as llvmpipe_frame.ppm (P6, top row first, linear colour
 * clamped to 8 bits, no gamma, as rayforge writes its canvas).
 *
 * Build:  cc -O2 -o llvmpipe_frame frame.c -lOSMesa -lm
 * Run:    LP_NUM_THREADS=2 ./llvmpipe_frame [FRAMES]      (FRAMES defaults to 10)
 *         LP_NUM_THREADS=1 ./llvmpipe_frame 10
 */
#define GL_GLEXT_PROTOTYPES 1
#include <GL/osmesa.h>
#include <GL/gl.h>
#include <GL/glext.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define WIDTH 1920
#define HEIGHT 1080
#define N 708

static double height_at(double x, double z) {
    return 0.15 * sin(3.0 * x) * cos(2.0 * z) + 0.05 * sin(7.0 * (x + z));
}

static double now_ms(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec * 1e3 + t.tv_nsec / 1e6;
}

static void cross3(const double a[3], const double b[3], double out[3]) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static void normalize3(double v[3]) {
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    v[0] /= l; v[1] /= l; v[2] /= l;
}

/* out = a * b, 4x4 row-major. */
static void mul4(const double a[16], const double b[16], double out[16]) {
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++) {
            double s = 0;
            for (int k = 0; k < 4; k++) s += a[r * 4 + k] * b[k * 4 + c];
            out[r * 4 + c] = s;
        }
}

static const char *vertex_src =
    "#version 330 core\n"
    "layout(location = 0) in vec3 position;\n"
    "layout(location = 1) in vec3 normal;\n"
    "uniform mat4 mvp;\n"
    "out vec3 world_pos;\n"
    "out vec3 world_normal;\n"
    "void main() {\n"
    "  world_pos = position;\n"
    "  world_normal = normal;\n"
    "  gl_Position = mvp * vec4(position, 1.0);\n"
    "}\n";

/* The book's lighting(), summed over the two point lights (no falloff, no shadows). */
static const char *fragment_src =
    "#version 330 core\n"
    "in vec3 world_pos;\n"
    "in vec3 world_normal;\n"
    "uniform vec3 eye;\n"
    "out vec4 colour;\n"
    "const vec3 surface = vec3(0.4, 0.7, 0.3);\n"
    "const float ambient = 0.1, diffuse = 0.9, specular = 0.3, shininess = 200.0;\n"
    "vec3 light(vec3 pos, vec3 intensity, vec3 n, vec3 eyev) {\n"
    "  vec3 effective = surface * intensity;\n"
    "  vec3 result = effective * ambient;\n"
    "  vec3 l = normalize(pos - world_pos);\n"
    "  float ldn = dot(l, n);\n"
    "  if (ldn < 0.0) return result;\n"
    "  result += effective * diffuse * ldn;\n"
    "  float rde = dot(reflect(-l, n), eyev);\n"
    "  if (rde > 0.0) result += intensity * specular * pow(rde, shininess);\n"
    "  return result;\n"
    "}\n"
    "void main() {\n"
    "  vec3 eyev = normalize(eye - world_pos);\n"
    "  vec3 n = normalize(world_normal);\n"
    "  if (dot(n, eyev) < 0.0) n = -n;\n"
    "  vec3 c = light(vec3(-10.0, 10.0, -10.0), vec3(0.8, 0.8, 0.8), n, eyev)\n"
    "         + light(vec3(10.0, 5.0, -5.0), vec3(0.3, 0.3, 0.4), n, eyev);\n"
    "  colour = vec4(c, 1.0);\n"
    "}\n";

static GLuint compile(GLenum kind, const char *src) {
    GLuint s = glCreateShader(kind);
    glShaderSource(s, 1, &src, NULL);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[4096];
        glGetShaderInfoLog(s, sizeof log, NULL, log);
        fprintf(stderr, "shader: %s\n", log);
        exit(1);
    }
    return s;
}

int main(int argc, char **argv) {
    int frames = argc > 1 ? atoi(argv[1]) : 10;
    if (frames < 1) frames = 1;

    const int attribs[] = {
        OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24, OSMESA_STENCIL_BITS, 0,
        OSMESA_ACCUM_BITS, 0, OSMESA_PROFILE, OSMESA_CORE_PROFILE,
        OSMESA_CONTEXT_MAJOR_VERSION, 3, OSMESA_CONTEXT_MINOR_VERSION, 3, 0};
    OSMesaContext ctx = OSMesaCreateContextAttribs(attribs, NULL);
    if (!ctx) { fprintf(stderr, "OSMesaCreateContextAttribs failed\n"); return 1; }
    unsigned char *buffer = malloc((size_t)WIDTH * HEIGHT * 4);
    if (!OSMesaMakeCurrent(ctx, buffer, GL_UNSIGNED_BYTE, WIDTH, HEIGHT)) {
        fprintf(stderr, "OSMesaMakeCurrent failed\n"); return 1;
    }
    printf("GL_RENDERER: %s\nGL_VERSION: %s\n", glGetString(GL_RENDERER), glGetString(GL_VERSION));

    /* The mesh, computed in double as rayforge does, stored as float. */
    const int side = N + 1;
    const size_t nverts = (size_t)side * side;
    float *verts = malloc(nverts * 6 * sizeof(float));
    const double e = 1e-4;
    for (int j = 0; j <= N; j++)
        for (int i = 0; i <= N; i++) {
            double x = -4.0 + 8.0 * i / N, z = -4.0 + 8.0 * j / N;
            double dx = (height_at(x + e, z) - height_at(x - e, z)) / (2.0 * e);
            double dz = (height_at(x, z + e) - height_at(x, z - e)) / (2.0 * e);
            double nrm[3] = {-dx, 1.0, -dz};
            normalize3(nrm);
            float *v = verts + ((size_t)j * side + i) * 6;
            v[0] = (float)x; v[1] = (float)height_at(x, z); v[2] = (float)z;
            v[3] = (float)nrm[0]; v[4] = (float)nrm[1]; v[5] = (float)nrm[2];
        }
    const size_t nidx = (size_t)N * N * 6;
    GLuint *idx = malloc(nidx * sizeof(GLuint));
    size_t k = 0;
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++) {
            GLuint a = j * side + i, b = j * side + i + 1;
            GLuint c = (j + 1) * side + i + 1, d = (j + 1) * side + i;
            idx[k++] = a; idx[k++] = b; idx[k++] = c;
            idx[k++] = a; idx[k++] = c; idx[k++] = d;
        }

    GLuint vao, vbo, ibo;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glGenBuffers(1, &vbo);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, nverts * 6 * sizeof(float), verts, GL_STATIC_DRAW);
    glGenBuffers(1, &ibo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, nidx * sizeof(GLuint), idx, GL_STATIC_DRAW);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), (void *)0);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), (void *)(3 * sizeof(float)));
    glEnableVertexAttribArray(0);
    glEnableVertexAttribArray(1);

    GLuint prog = glCreateProgram();
    glAttachShader(prog, compile(GL_VERTEX_SHADER, vertex_src));
    glAttachShader(prog, compile(GL_FRAGMENT_SHADER, fragment_src));
    glLinkProgram(prog);
    GLint linked = 0;
    glGetProgramiv(prog, GL_LINK_STATUS, &linked);
    if (!linked) { fprintf(stderr, "link failed\n"); return 1; }
    glUseProgram(prog);

    /* The book's camera: view_transform(from, to, up); camera space has +x to the image's
     * left and looks down -z. GL eye space has +x to the right, so mirror x, then a
     * perspective whose viewport at distance 1 is [-hw, hw] x [-hh, hh]. */
    const double from[3] = {0.0, 2.5, -5.5}, to[3] = {0.0, 0.0, 0.5}, up[3] = {0.0, 1.0, 0.0};
    double fwd[3] = {to[0] - from[0], to[1] - from[1], to[2] - from[2]};
    normalize3(fwd);
    double upn[3] = {up[0], up[1], up[2]};
    normalize3(upn);
    double left[3], true_up[3];
    cross3(fwd, upn, left);
    cross3(left, fwd, true_up);
    double orient[16] = {
        left[0], left[1], left[2], 0,
        true_up[0], true_up[1], true_up[2], 0,
        -fwd[0], -fwd[1], -fwd[2], 0,
        0, 0, 0, 1};
    double translate[16] = {1, 0, 0, -from[0], 0, 1, 0, -from[1], 0, 0, 1, -from[2], 0, 0, 0, 1};
    double view[16];
    mul4(orient, translate, view);
    const double half_view = tan(1.0 / 2.0), aspect = (double)WIDTH / HEIGHT;
    const double hw = aspect >= 1 ? half_view : half_view * aspect;
    const double hh = aspect >= 1 ? half_view / aspect : half_view;
    const double nearp = 0.05, farp = 50.0;
    double proj[16] = {
        -1.0 / hw, 0, 0, 0, /* the minus mirrors x */
        0, 1.0 / hh, 0, 0,
        0, 0, -(farp + nearp) / (farp - nearp), -2.0 * farp * nearp / (farp - nearp),
        0, 0, -1, 0};
    double mvp_d[16];
    mul4(proj, view, mvp_d);
    float mvp[16];
    for (int i = 0; i < 16; i++) mvp[i] = (float)mvp_d[i];
    glUniformMatrix4fv(glGetUniformLocation(prog, "mvp"), 1, GL_TRUE, mvp);
    glUniform3f(glGetUniformLocation(prog, "eye"), (float)from[0], (float)from[1], (float)from[2]);

    glViewport(0, 0, WIDTH, HEIGHT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_CULL_FACE);
    glClearColor(0.1f, 0.1f, 0.15f, 1.0f);
    glFinish();

    double total = 0, best = 1e300, first = 0;
    for (int f = 0; f < frames; f++) {
        double t0 = now_ms();
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        glDrawElements(GL_TRIANGLES, (GLsizei)nidx, GL_UNSIGNED_INT, (void *)0);
        glFinish();
        double dt = now_ms() - t0;
        if (f == 0) first = dt;
        total += dt;
        if (dt < best) best = dt;
    }
    GLenum err = glGetError();
    if (err != GL_NO_ERROR) fprintf(stderr, "GL error 0x%x\n", err);
    printf("frames %d: first %.1f ms, mean %.1f ms, mean after first %.1f ms, best %.1f ms\n",
           frames, first, total / frames, frames > 1 ? (total - first) / (frames - 1) : first, best);

    /* OSMesa's buffer holds the bottom row first. */
    FILE *out = fopen("llvmpipe_frame.ppm", "wb");
    if (!out) { perror("llvmpipe_frame.ppm"); return 1; }
    fprintf(out, "P6\n%d %d\n255\n", WIDTH, HEIGHT);
    unsigned char *row = malloc(WIDTH * 3);
    for (int y = HEIGHT - 1; y >= 0; y--) {
        const unsigned char *src = buffer + (size_t)y * WIDTH * 4;
        for (int x = 0; x < WIDTH; x++) memcpy(row + x * 3, src + x * 4, 3);
        fwrite(row, 3, WIDTH, out);
    }
    fclose(out);
    OSMesaDestroyContext(ctx);
    return 0;
}
