/* libFuzzer target: database configs in JSON. Any input must parse or fail with an error. */
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <mm/config_json.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    mm_error err;
    memset(&err, 0, sizeof err);
    if (mm_config_parse_json((const char *)data, size, "fuzz.json", "/nonexistent", &cfg, &err) == MM_OK) {
        for (int i = 0; i < cfg.clip_count; ++i) (void)mm_config_tag_index(&cfg, cfg.clips[i].name);
        mm_config_free(&cfg);
    } else if (err.message[0] == 0) {
        __builtin_trap(); /* every failure must say why */
    }
    return 0;
}
