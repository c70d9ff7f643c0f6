/* See fmu_model.h: the variable groups of a model, unrolled into single variables. */
#include <stdio.h>

#include "fmu_model.h"

/* name_format with its "%d" replaced by the indices in turn (no printf: the format is data). */
static void format_name(char *out, size_t size, const char *format, int i1, int i2)
{
    const int indices[2] = {i1, i2};
    int used = 0;
    size_t n = 0;
    for (const char *p = format; *p && n + 1 < size; ++p) {
        if (p[0] == '%' && p[1] == 'd' && used < 2) {
            n += (size_t)snprintf(out + n, size - n, "%d", indices[used++]);
            ++p;
            if (n >= size) n = size - 1;
        } else {
            out[n++] = *p;
        }
    }
    out[n] = '\0';
}

static int group_size(const fmu_variable_group *g)
{
    return (g->count1 > 0 ? g->count1 : 1) * (g->count2 > 0 ? g->count2 : 1);
}

int fmu_variable_count(const fmu_variable_group *groups, int num_groups)
{
    int n = 0;
    for (int i = 0; i < num_groups; ++i) n += group_size(&groups[i]);
    return n;
}

int fmu_variable_at(const fmu_variable_group *groups, int num_groups, int index, fmu_variable *out)
{
    for (int i = 0; i < num_groups; ++i) {
        const fmu_variable_group *g = &groups[i];
        const int size = group_size(g);
        if (index >= size) {
            index -= size;
            continue;
        }
        const int c2 = g->count2 > 0 ? g->count2 : 1, i1 = index / c2, i2 = index % c2;
        format_name(out->name, sizeof out->name, g->name_format, i1 + 1, i2 + 1);
        out->type = g->type;
        out->causality = g->causality;
        out->variability = g->variability;
        out->offset = g->offset + (size_t)i1 * g->stride1 + (size_t)i2 * g->stride2;
        out->start = g->start;
        out->unit = g->unit;
        out->description = g->description;
        return 0;
    }
    return -1;
}
