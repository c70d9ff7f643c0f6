/* SPDX-License-Identifier: Apache-2.0 */
/*
 * FMU states for masters that roll back (FMI 2 fmi2GetFMUstate..., FMI 3 fmi3GetFMUState...): a
 * copy of the instance's time and state, of the model data and of the blocks the model allocated
 * (the identifier's arrays and its okid workspace). Everything is fixed memory, so a state is one
 * allocation of a size known at the time it is taken, through the instance's allocator.
 *
 * The identifier's okid_identifier points into its workspace, and lib/ has no relocation: such a
 * state restores only into the instance whose blocks (address and size) it copied. A model whose
 * data holds no pointers (the plant) has portable states, which serialize.
 */
#include <stdint.h>
#include <string.h>

#include "fmu_instance.h"

#define STATE_MAGIC 0x464d5553u /* "FMUS" */

typedef struct saved_state {
    uint32_t magic;
    uint32_t model;     /* FNV-1a of the model name and its data size: refuses another model's bytes */
    size_t total;       /* bytes of the whole state: this header, the model data, the blocks' contents */
    fmu_state state;
    double time, start_time, stop_time;
    int has_stop_time;
    int num_blocks;
    fmu_block blocks[FMU_MAX_BLOCKS];
} saved_state;

/* The header rounded up so that the model data behind it is aligned for any of its members. */
enum { HEADER_BYTES = (sizeof(saved_state) + 15) / 16 * 16 };

static uint32_t model_identity(void)
{
    unsigned long h = fmu_hash(FMU_MODEL.name, strlen(FMU_MODEL.name));
    const size_t bytes = FMU_MODEL.data_bytes;
    return (uint32_t)(h ^ fmu_hash(&bytes, sizeof bytes));
}

static int blocks_now(fmu_instance *inst, fmu_block blocks[FMU_MAX_BLOCKS])
{
    return FMU_MODEL.state_blocks ? FMU_MODEL.state_blocks(inst->data, blocks) : 0;
}

int fmu_state_portable(void) { return FMU_MODEL.state_blocks == NULL; }

static const unsigned STATE_ACCESS =
    FMU_STATE_INSTANTIATED | FMU_STATE_INITIALIZATION | FMU_STATE_STEP | FMU_STATE_TERMINATED | FMU_STATE_ERROR;

fmu_status fmu_get_state(fmu_instance *inst, void **state)
{
    if (fmu_check(inst, STATE_ACCESS, "GetFMUState") != FMU_OK) return FMU_ERROR;
    if (state == NULL) return fmu_refuse(inst, "GetFMUState: NULL state pointer");
    fmu_block blocks[FMU_MAX_BLOCKS];
    const int n = blocks_now(inst, blocks);
    size_t total = HEADER_BYTES + FMU_MODEL.data_bytes;
    for (int i = 0; i < n; ++i) total += blocks[i].bytes;
    saved_state *s = *state;
    if (s != NULL && (s->magic != STATE_MAGIC || s->total != total)) { /* reuse it only when it fits */
        inst->memory.release(s);
        s = NULL;
    }
    if (s == NULL) s = inst->memory.allocate(1, total);
    *state = s;
    if (s == NULL) return fmu_refuse(inst, "GetFMUState: out of memory for a state of %zu bytes", total);
    memset(s, 0, HEADER_BYTES); /* no stray bytes in a serialization */
    s->magic = STATE_MAGIC;
    s->model = model_identity();
    s->total = total;
    s->state = inst->state;
    s->time = inst->time;
    s->start_time = inst->start_time;
    s->stop_time = inst->stop_time;
    s->has_stop_time = inst->has_stop_time;
    s->num_blocks = n;
    unsigned char *at = (unsigned char *)s + HEADER_BYTES;
    memcpy(at, inst->data, FMU_MODEL.data_bytes);
    at += FMU_MODEL.data_bytes;
    for (int i = 0; i < n; ++i) {
        s->blocks[i] = blocks[i];
        if (blocks[i].bytes) memcpy(at, blocks[i].at, blocks[i].bytes);
        at += blocks[i].bytes;
    }
    return FMU_OK;
}

/* A state this build wrote, of this size; 0 when it is not. */
static int well_formed(const saved_state *s, size_t size)
{
    return s != NULL && size >= HEADER_BYTES && s->magic == STATE_MAGIC && s->model == model_identity() &&
           s->total == size && s->num_blocks >= 0 && s->num_blocks <= FMU_MAX_BLOCKS;
}

fmu_status fmu_set_state(fmu_instance *inst, const void *state)
{
    if (fmu_check(inst, STATE_ACCESS, "SetFMUState") != FMU_OK) return FMU_ERROR;
    const saved_state *s = state;
    if (s == NULL || !well_formed(s, s->total)) return fmu_refuse(inst, "SetFMUState: not a state of %s", FMU_MODEL.name);
    fmu_block blocks[FMU_MAX_BLOCKS];
    const int n = blocks_now(inst, blocks);
    int same = n == s->num_blocks;
    for (int i = 0; same && i < n; ++i) same = blocks[i].at == s->blocks[i].at && blocks[i].bytes == s->blocks[i].bytes;
    if (!same) {
        return fmu_refuse(inst, "SetFMUState: the state was taken from another instance or before its memory was "
                                "allocated again (Reset, configuration, initialization): the identifier's workspace "
                                "holds pointers into itself, so its state restores only into the same memory");
    }
    const unsigned char *at = (const unsigned char *)s + HEADER_BYTES;
    memcpy(inst->data, at, FMU_MODEL.data_bytes);
    at += FMU_MODEL.data_bytes;
    for (int i = 0; i < n; ++i) {
        if (blocks[i].bytes) memcpy(blocks[i].at, at, blocks[i].bytes);
        at += blocks[i].bytes;
    }
    inst->state = s->state;
    inst->time = s->time;
    inst->start_time = s->start_time;
    inst->stop_time = s->stop_time;
    inst->has_stop_time = s->has_stop_time;
    return FMU_OK;
}

fmu_status fmu_free_state(fmu_instance *inst, void **state)
{
    if (fmu_check(inst, ~0u, "FreeFMUState") != FMU_OK) return FMU_ERROR;
    if (state != NULL && *state != NULL) {
        inst->memory.release(*state);
        *state = NULL;
    }
    return FMU_OK;
}

static fmu_status check_portable(fmu_instance *inst, const char *function)
{
    if (fmu_check(inst, ~0u, function) != FMU_OK) return FMU_ERROR;
    if (!fmu_state_portable()) {
        return fmu_refuse(inst, "%s: %s's state holds its okid workspace, which points into itself: it cannot be "
                                "restored elsewhere, so it is not serialized (canSerializeFMUstate is false)",
                          function, FMU_MODEL.name);
    }
    return FMU_OK;
}

fmu_status fmu_serialized_size(fmu_instance *inst, const void *state, size_t *size)
{
    if (check_portable(inst, "SerializedFMUStateSize") != FMU_OK) return FMU_ERROR;
    const saved_state *s = state;
    if (s == NULL || size == NULL || !well_formed(s, s->total)) {
        return fmu_refuse(inst, "SerializedFMUStateSize: not a state of %s", FMU_MODEL.name);
    }
    *size = s->total;
    return FMU_OK;
}

/* A portable state has no pointers: its bytes are its serialization. */
fmu_status fmu_serialize(fmu_instance *inst, const void *state, unsigned char *bytes, size_t size)
{
    if (check_portable(inst, "SerializeFMUState") != FMU_OK) return FMU_ERROR;
    const saved_state *s = state;
    if (s == NULL || bytes == NULL || !well_formed(s, s->total) || size < s->total) {
        return fmu_refuse(inst, "SerializeFMUState: not a state of %s, or fewer than its %zu bytes given",
                          FMU_MODEL.name, s ? s->total : (size_t)0);
    }
    memcpy(bytes, s, s->total);
    return FMU_OK;
}

fmu_status fmu_deserialize(fmu_instance *inst, const unsigned char *bytes, size_t size, void **state)
{
    if (check_portable(inst, "DeserializeFMUState") != FMU_OK) return FMU_ERROR;
    saved_state header;
    if (bytes == NULL || state == NULL || size < HEADER_BYTES) {
        return fmu_refuse(inst, "DeserializeFMUState: %zu bytes are no state of %s", size, FMU_MODEL.name);
    }
    memcpy(&header, bytes, sizeof header); /* the caller's bytes need not be aligned */
    if (!well_formed(&header, size) || header.num_blocks != 0) {
        return fmu_refuse(inst, "DeserializeFMUState: the bytes are not a serialized state of this build of %s",
                          FMU_MODEL.name);
    }
    if (*state != NULL) inst->memory.release(*state); /* a state of this instance, given for reuse */
    void *s = inst->memory.allocate(1, size);
    *state = s;
    if (s == NULL) return fmu_refuse(inst, "DeserializeFMUState: out of memory for %zu bytes", size);
    memcpy(s, bytes, size);
    return FMU_OK;
}
