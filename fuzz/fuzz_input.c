/* libFuzzer target: input scripts in JSON. Any bytes parse or fail with a message; a parsed
 * script samples safely at any time. */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <mm/input_json.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    mm_input_script s;
    mm_error err;
    memset(&err, 0, sizeof err);
    if (mm_input_script_parse_json((const char *)data, size, "fuzz.json", &s, &err) == MM_OK) {
        const float times[5] = {-1.0f, 0.0f, 1.5f, 1e9f, NAN};
        mm_input in;
        for (int i = 0; i < 5; ++i) mm_input_script_sample(&s, times[i], &in);
        mm_input_script_free(&s);
    } else if (err.message[0] == 0) {
        __builtin_trap();
    }
    return 0;
}
