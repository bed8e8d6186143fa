/* mm/move_kind.h - the kinds of moves beyond locomotion: jump, vault (low and high), climb and
 * drop-down.
 *
 * The vocabulary shared by the detector that finds the moves in motion capture (mm/move_detect.h,
 * offline) and the layer that plays them on a scene (mm/moves.h, which names them:
 * mm_move_kind_name). Values are indices, 0 .. MM_MOVE_KIND_COUNT - 1, or MM_MOVE_NONE.
 *
 * Functions: none (an enum only).
 */
#ifndef MM_MOVE_KIND_H
#define MM_MOVE_KIND_H

#ifdef __cplusplus
extern "C" {
#endif

typedef enum mm_move_kind {
    MM_MOVE_NONE = -1,
    MM_MOVE_JUMP = 0,
    MM_MOVE_VAULT_LOW,
    MM_MOVE_VAULT_HIGH,
    MM_MOVE_CLIMB,
    MM_MOVE_DROP,
    MM_MOVE_KIND_COUNT
} mm_move_kind;

#ifdef __cplusplus
}
#endif

#endif /* MM_MOVE_KIND_H */
