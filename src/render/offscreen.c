/* Offscreen rendering through OSMesa: Mesa's software rasteriser draws into memory, so frames can
 * be made without a display or a GPU (CI, servers). */
#include <stdlib.h>
#include <string.h>

#include <GL/osmesa.h>

#include <mm/render.h>

struct mm_offscreen {
    OSMesaContext context;
    int width, height;
    unsigned char *rgba; /* what OSMesa draws into: bottom row first */
    uint8_t *rgb;        /* the image handed out: top row first */
    mm_renderer *renderer;
};

static mm_gl_proc load(const char *name)
{
    /* OSMESAproc is declared without a prototype; the renderer casts it to the right type */
    return (mm_gl_proc)OSMesaGetProcAddress(name);
}

mm_result mm_offscreen_create(int width, int height, mm_offscreen **out, mm_error *err)
{
    *out = NULL;
    if (width < 1 || width > 4096 || height < 1 || height > 4096)
        return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "image size %d x %d: each side must be 1 to 4096",
                            width, height);
    mm_offscreen *o = calloc(1, sizeof *o);
    if (!o) return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    o->width = width;
    o->height = height;
    o->rgba = malloc((size_t)width * (size_t)height * 4);
    o->rgb = malloc((size_t)width * (size_t)height * 3);
    if (!o->rgba || !o->rgb) {
        mm_offscreen_destroy(o);
        return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory for a %d x %d image", width,
                            height);
    }
    const int attributes[] = {OSMESA_FORMAT,
                              OSMESA_RGBA,
                              OSMESA_DEPTH_BITS,
                              24,
                              OSMESA_PROFILE,
                              OSMESA_CORE_PROFILE,
                              OSMESA_CONTEXT_MAJOR_VERSION,
                              3,
                              OSMESA_CONTEXT_MINOR_VERSION,
                              3,
                              0};
    o->context = OSMesaCreateContextAttribs(attributes, NULL);
    if (!o->context) {
        mm_offscreen_destroy(o);
        return mm_error_set(err, MM_ERR_UNSUPPORTED, 0, 0, "OSMesa cannot make an OpenGL 3.3 core context");
    }
    if (!OSMesaMakeCurrent(o->context, o->rgba, GL_UNSIGNED_BYTE, width, height)) {
        mm_offscreen_destroy(o);
        return mm_error_set(err, MM_ERR_UNSUPPORTED, 0, 0, "OSMesa cannot make its context current");
    }
    mm_result r = mm_renderer_create(load, &o->renderer, err);
    if (r != MM_OK) {
        mm_offscreen_destroy(o);
        return r;
    }
    *out = o;
    return MM_OK;
}

const uint8_t *mm_offscreen_render(mm_offscreen *o, const mm_camera *cam, const mm_render_scene *scene)
{
    if (!o || !o->context) return NULL;
    if (OSMesaGetCurrentContext() != o->context &&
        !OSMesaMakeCurrent(o->context, o->rgba, GL_UNSIGNED_BYTE, o->width, o->height))
        return NULL;
    mm_renderer_draw(o->renderer, cam, o->width, o->height, scene);
    glFinish();
    size_t w = (size_t)o->width;
    for (int y = 0; y < o->height; ++y) {
        const unsigned char *src = o->rgba + (size_t)(o->height - 1 - y) * w * 4;
        uint8_t *dst = o->rgb + (size_t)y * w * 3;
        for (size_t x = 0; x < w; ++x) memcpy(dst + 3 * x, src + 4 * x, 3);
    }
    return o->rgb;
}

void mm_offscreen_destroy(mm_offscreen *o)
{
    if (!o) return;
    if (o->renderer) {
        OSMesaMakeCurrent(o->context, o->rgba, GL_UNSIGNED_BYTE, o->width, o->height);
        mm_renderer_destroy(o->renderer);
    }
    if (o->context) {
        OSMesaMakeCurrent(NULL, NULL, 0, 0, 0); /* releases the framebuffer OSMesa made for o->rgba */
        OSMesaDestroyContext(o->context);
    }
    free(o->rgba);
    free(o->rgb);
    free(o);
}

void mm_offscreen_size(const mm_offscreen *o, int *width, int *height)
{
    if (width) *width = o ? o->width : 0;
    if (height) *height = o ? o->height : 0;
}
