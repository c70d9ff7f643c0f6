/* SPDX-License-Identifier: Apache-2.0 */
/* See fmu_model.h: the variable table of a model, its arrays sized by the structural parameters. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmu_model.h"

size_t fmu_group_dim(const fmu_model *model, const void *data, int g, int d)
{
    const int dim = model->groups[g].dims[d];
    if (dim < 0) return (size_t)-dim;
    if (dim == 0) return 0;
    int value;
    memcpy(&value, (const char *)data + model->groups[dim - 1].offset, sizeof value);
    return value > 0 ? (size_t)value : 0;
}

size_t fmu_group_size(const fmu_model *model, const void *data, int g)
{
    if (model->groups[g].dims[0] == 0) return 1;
    size_t n = 1;
    for (int d = 0; d < FMU_MAX_DIMS && model->groups[g].dims[d] != 0; ++d) n *= fmu_group_dim(model, data, g, d);
    return n;
}

static size_t value_bytes(fmu_type type) { return type == FMU_REAL ? sizeof(double) : sizeof(int); }

void *fmu_group_element(const fmu_model *model, void *data, int g, size_t e)
{
    const fmu_variable_group *v = &model->groups[g];
    char *at = (char *)data + v->offset;
    if (v->dims[0] == 0) return at;
    char *array;
    memcpy(&array, at, sizeof array);
    return array ? array + e * value_bytes(v->type) : NULL;
}

size_t fmu_flat_count(const fmu_model *model, const void *data)
{
    size_t n = 0;
    for (int g = 0; g < model->num_groups; ++g) n += fmu_group_size(model, data, g);
    return n;
}

int fmu_flat_find(const fmu_model *model, const void *data, unsigned vr, int *group, size_t *element)
{
    if (vr == 0) return -1;
    size_t index = vr - 1u;
    for (int g = 0; g < model->num_groups; ++g) {
        const size_t size = fmu_group_size(model, data, g);
        if (index < size) {
            *group = g;
            *element = index;
            return 0;
        }
        index -= size;
    }
    return -1;
}

void fmu_flat_name(const fmu_model *model, const void *data, int g, size_t e, char *out, size_t size)
{
    const fmu_variable_group *v = &model->groups[g];
    if (v->dims[0] == 0 || v->flat_name == NULL) {
        snprintf(out, size, "%s", v->name);
        return;
    }
    /* first index over the first dimension, second over the rest; "%d" is data, not a printf format */
    const size_t inner = fmu_group_size(model, data, g) / (fmu_group_dim(model, data, g, 0) ? fmu_group_dim(model, data, g, 0) : 1);
    const size_t indices[2] = {e / (inner ? inner : 1) + 1, e % (inner ? inner : 1) + 1};
    int used = 0;
    size_t n = 0;
    for (const char *p = v->flat_name; *p && n + 1 < size; ++p) {
        if (p[0] == '%' && p[1] == 'd' && used < 2) {
            n += (size_t)snprintf(out + n, size - n, "%zu", indices[used++]);
            ++p;
            if (n >= size) n = size - 1;
        } else {
            out[n++] = *p;
        }
    }
    out[n] = '\0';
}

int fmu_group_by_name(const fmu_model *model, const char *name)
{
    for (int g = 0; g < model->num_groups; ++g) {
        if (strcmp(model->groups[g].name, name) == 0) return g;
    }
    return -1;
}

unsigned long fmu_hash(const void *bytes, size_t count)
{
    unsigned long h = 2166136261ul;
    for (size_t i = 0; i < count; ++i) {
        h ^= ((const unsigned char *)bytes)[i];
        h = (h * 16777619ul) & 0xfffffffful;
    }
    return h;
}

int fmu_apply_config(const fmu_model *model, void *data, const char *config, char *error, size_t error_size)
{
    char line[256];
    for (const char *p = config; *p;) {
        const size_t len = strcspn(p, "\n");
        snprintf(line, sizeof line, "%.*s", (int)(len < sizeof line ? len : sizeof line - 1), p);
        p += len + (p[len] == '\n');
        line[strcspn(line, "\r")] = '\0';
        char name[128], rest[2];
        double value;
        if (sscanf(line, "%127s", name) != 1 || name[0] == '#') continue;
        const int g = fmu_group_by_name(model, name);
        if (g < 0 || model->groups[g].dims[0] != 0 || model->groups[g].causality == FMU_OUTPUT ||
            model->groups[g].causality == FMU_INPUT || sscanf(line, "%*s %lf %1s", &value, rest) != 1) {
            snprintf(error, error_size, "line '%s' is not '<structural parameter or parameter> <number>'", line);
            return -1;
        }
        void *at = fmu_group_element(model, data, g, 0);
        if (model->groups[g].type == FMU_REAL) {
            memcpy(at, &value, sizeof value);
            continue;
        }
        if (!(value >= -2147483648.0 && value <= 2147483647.0) || value != (double)(long)value) {
            snprintf(error, error_size, "%s = %.17g is not an integer", name, value);
            return -1;
        }
        const int i = (int)value;
        memcpy(at, &i, sizeof i);
    }
    return 0;
}
