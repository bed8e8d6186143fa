/* libFuzzer target for the BVH reader: parses the input and, when it is accepted, uses the result
 * the way a program would (conversion to a clip, forward kinematics on the first and last frame,
 * writing it back as BVH). Any crash, sanitizer report, leak or broken invariant is a bug.
 *
 * Built by fuzz/CMakeLists.txt (-DMM_BUILD_FUZZ=ON, clang); run with scripts/fuzz.sh. Define
 * MM_FUZZ_ROUND_TRIP to also require that what the writer produces reads back. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <mm/bvh.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* Stops the fuzzer with a crash that libFuzzer records as an artifact. */
#define FUZZ_CHECK(cond)                                                                                     \
    do {                                                                                                     \
        if (!(cond)) __builtin_trap();                                                                       \
    } while (0)

static int all_zero(const void *p, size_t n)
{
    const unsigned char *b = (const unsigned char *)p;
    for (size_t i = 0; i < n; ++i)
        if (b[i]) return 0;
    return 1;
}

static void use_clip(const mm_clip *clip)
{
    char *text = NULL;
    size_t text_size = 0;
    mm_error err;
    if (mm_bvh_write(clip, NULL, &text, &text_size, &err) != MM_OK) {
        FUZZ_CHECK(text == NULL);
        return;
    }
    FUZZ_CHECK(text != NULL && text_size > 0 && text[text_size] == 0);
#ifdef MM_FUZZ_ROUND_TRIP
    mm_bvh again;
    FUZZ_CHECK(mm_bvh_parse(text, text_size, NULL, &again, &err) == MM_OK);
    FUZZ_CHECK(again.skeleton.joint_count == clip->skeleton.joint_count);
    FUZZ_CHECK(again.frame_count == clip->frame_count);
    mm_bvh_free(&again);
#endif
    mm_free(NULL, text);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    mm_bvh bvh;
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_result r = mm_bvh_parse((const char *)data, size, NULL, &bvh, &err);
    if (r != MM_OK) {
        /* A failure names a real error code and leaves nothing behind. */
        FUZZ_CHECK(r > MM_OK && r < MM_RESULT_COUNT && err.code == r && err.message[0] != 0);
        FUZZ_CHECK(all_zero(&bvh, sizeof bvh));
        return 0;
    }
    int joints = bvh.skeleton.joint_count, frames = bvh.frame_count;
    FUZZ_CHECK(joints >= 1 && joints <= MM_MAX_JOINTS && bvh.channel_count >= 1 && frames >= 0);
    FUZZ_CHECK(bvh.frame_time > 0.0);

    double *xyz = (double *)malloc(3 * sizeof(double) * (size_t)joints);
    FUZZ_CHECK(xyz != NULL);
    if (frames > 0) {
        FUZZ_CHECK(mm_bvh_fk(&bvh, 0, xyz) == MM_OK);
        FUZZ_CHECK(mm_bvh_fk(&bvh, frames - 1, xyz) == MM_OK);
    }
    FUZZ_CHECK(mm_bvh_fk(&bvh, frames, xyz) == MM_ERR_OUT_OF_RANGE);
    free(xyz);
    (void)mm_bvh_detect_scale(&bvh, NULL);

    /* A clip costs 28 bytes per joint and frame whatever the channels; a small input with many
     * channel-less joints could ask for gigabytes, which is legitimate, so bound it here. */
    if ((size_t)frames * (size_t)joints <= ((size_t)1 << 22)) {
        mm_clip clip;
        if (mm_bvh_to_clip(&bvh, NULL, &clip, &err) == MM_OK) {
            FUZZ_CHECK(clip.frame_count == frames && clip.skeleton.joint_count == joints);
            use_clip(&clip);
            mm_clip_free(&clip);
        }
    }
    mm_bvh_free(&bvh);
    return 0;
}
