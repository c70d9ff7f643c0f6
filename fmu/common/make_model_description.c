/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Writes a model's modelDescription.xml (FMI 2.0 or 3.0) from the same variable table and start
 * values the FMU runs on, so the description and the binary cannot disagree.
 *   make_model_description 2 CONFIG|- SOURCE...  > modelDescription.xml  (FMI 2, for the sizes and
 *                                                  defaults of CONFIG, the resources/<model>.cfg)
 *   make_model_description 3 > modelDescription.xml
 *   make_model_description build SOURCE... > buildDescription.xml        (FMI 3 sources/)
 *   make_model_description table > model_variables.json                  (the table and start values,
 *                                                  from which okid_tools.fmu_generator writes the FMI 2
 *                                                  description of any configuration: a test compares
 *                                                  its text with this program's)
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmu_model.h"
#include "okid/okid.h"

/* The models log through this; describing them logs nothing. */
void fmu_log(fmu_logger *logger, fmu_status status, const char *category, const char *format, ...)
{
    (void)logger, (void)status, (void)category, (void)format;
}

static void *allocate(size_t count, size_t size) { return calloc(count, size); }
static const fmu_allocator MEMORY = {allocate, free};

static void escaped(const char *text)
{
    for (const char *p = text; *p; ++p) {
        switch (*p) {
        case '"': fputs("&quot;", stdout); break;
        case '&': fputs("&amp;", stdout); break;
        case '<': fputs("&lt;", stdout); break;
        case '>': fputs("&gt;", stdout); break;
        default: putchar(*p);
        }
    }
}

static void attr(const char *name, const char *text)
{
    printf(" %s=\"", name);
    escaped(text);
    putchar('"');
}

static const fmu_variable_group *group(int g) { return &FMU_MODEL.groups[g]; }

/* FMI 3 rolls back through states too; only a portable state is serialized (fmu_state.c). */
static const char *serializable(void) { return FMU_MODEL.state_blocks == NULL ? "true" : "false"; }

/* Sources fmpy and users compile: C files and the Eigen backend (C++). */
static int compiled(const char *name)
{
    const size_t len = strlen(name);
    return (len > 2 && strcmp(name + len - 2, ".c") == 0) || (len > 4 && strcmp(name + len - 4, ".cpp") == 0);
}

/*
 * The direct dependencies of an output on inputs (<ModelStructure>): "" for none (it changes only
 * in DoStep, so a master closing a loop through it sees no algebraic loop), else every element of
 * the input it depends on, with a factor fixed after initialization.
 */
static void dependencies(void *data, int version, const fmu_variable_group *v)
{
    const int input = v->depends_on ? fmu_group_by_name(&FMU_MODEL, v->depends_on) : -1;
    printf(" dependencies=\"");
    if (input < 0) {
        putchar('"');
        return;
    }
    size_t count = 1;
    if (version == 2) {
        unsigned first = 1;
        for (int g = 0; g < input; ++g) first += (unsigned)fmu_group_size(&FMU_MODEL, data, g);
        count = fmu_group_size(&FMU_MODEL, data, input);
        for (size_t e = 0; e < count; ++e) printf("%s%u", e ? " " : "", first + (unsigned)e);
    } else {
        printf("%d", input + 1);
    }
    printf("\" dependenciesKind=\"");
    for (size_t e = 0; e < count; ++e) printf("%sfixed", e ? " " : "");
    putchar('"');
}

static const char *causality(int version, fmu_causality c)
{
    switch (c) {
    case FMU_STRUCTURAL: return version == 3 ? "structuralParameter" : "calculatedParameter";
    case FMU_PARAMETER: return "parameter";
    case FMU_INPUT: return "input";
    default: return "output";
    }
}

static const char *variability(fmu_variability v)
{
    static const char *const names[] = {"fixed", "tunable", "discrete", "continuous"};
    return names[v];
}

/* Element e of group g as start-value text. */
static void value(void *data, int g, size_t e)
{
    const void *at = fmu_group_element(&FMU_MODEL, data, g, e);
    if (group(g)->type == FMU_REAL) {
        double v;
        memcpy(&v, at, sizeof v);
        printf("%.17g", v);
        return;
    }
    int v;
    memcpy(&v, at, sizeof v);
    if (group(g)->type == FMU_BOOLEAN) printf("%s", v ? "true" : "false");
    else printf("%d", v);
}

static void range(const fmu_variable_group *v)
{
    if (isnan(v->min) || isnan(v->max) || v->min > v->max || v->type == FMU_BOOLEAN) return;
    if (isfinite(v->min)) printf(v->type == FMU_REAL ? " min=\"%.17g\"" : " min=\"%.0f\"", v->min);
    if (isfinite(v->max)) printf(v->type == FMU_REAL ? " max=\"%.17g\"" : " max=\"%.0f\"", v->max);
}

static void units(void)
{
    const char *seen[32];
    int n = 0;
    for (int g = 0; g < FMU_MODEL.num_groups; ++g) {
        const char *unit = group(g)->unit;
        int known = unit == NULL;
        for (int j = 0; j < n && !known; ++j) known = strcmp(seen[j], unit) == 0;
        if (!known && n < 32) seen[n++] = unit;
    }
    if (n == 0) return;
    puts("  <UnitDefinitions>");
    for (int j = 0; j < n; ++j) printf("    <Unit name=\"%s\"/>\n", seen[j]);
    puts("  </UnitDefinitions>");
}

static void log_categories_and_experiment(void *data)
{
    puts("  <LogCategories>");
    puts("    <Category name=\"logEvents\" description=\"identifications and other events\"/>");
    puts("    <Category name=\"logStatusWarning\" description=\"rejected samples and other warnings\"/>");
    puts("    <Category name=\"logStatusError\" description=\"refused calls and parameters, with the reason\"/>");
    puts("    <Category name=\"logAll\" description=\"everything\"/>");
    puts("  </LogCategories>");
    double step = FMU_MODEL.default_step;
    const int dt = fmu_group_by_name(&FMU_MODEL, "dt");
    if (dt >= 0) memcpy(&step, fmu_group_element(&FMU_MODEL, data, dt, 0), sizeof step);
    printf("  <DefaultExperiment startTime=\"0\" stopTime=\"10\" stepSize=\"%.17g\"/>\n", step);
}

static void header(const char *version, const char *token_name, const char *token)
{
    puts("<?xml version=\"1.0\" encoding=\"UTF-8\"?>");
    printf("<fmiModelDescription fmiVersion=\"%s\"", version);
    attr("modelName", FMU_MODEL.name);
    attr("description", FMU_MODEL.description);
    printf(" generationTool=\"okid %s\"", OKID_VERSION_STRING);
    attr(token_name, token);
    printf(" variableNamingConvention=\"%s\"", version[0] == '2' ? "flat" : "structured");
}

static void fmi2(void *data, unsigned long config_hash, int num_sources, char **sources)
{
    char token[256], name[128];
    FMU_MODEL.token(data, 2, config_hash, token, sizeof token);
    header("2.0", "guid", token);
    puts(" numberOfEventIndicators=\"0\">");
    printf("  <CoSimulation modelIdentifier=\"%s\" canHandleVariableCommunicationStepSize=\"%s\""
           " canBeInstantiatedOnlyOncePerProcess=\"false\" canNotUseMemoryManagementFunctions=\"false\""
           " canGetAndSetFMUstate=\"true\" canSerializeFMUstate=\"%s\">\n",
           FMU_MODEL.name, FMU_MODEL.variable_step ? "true" : "false", serializable());
    puts("    <SourceFiles>");
    for (int i = 0; i < num_sources; ++i) {
        if (compiled(sources[i])) printf("      <File name=\"%s\"/>\n", sources[i]);
    }
    puts("    </SourceFiles>\n  </CoSimulation>");
    units();
    log_categories_and_experiment(data);
    puts("  <ModelVariables>");
    unsigned vr = 0;
    for (int g = 0; g < FMU_MODEL.num_groups; ++g) {
        const fmu_variable_group *v = group(g);
        const size_t size = fmu_group_size(&FMU_MODEL, data, g);
        for (size_t e = 0; e < size; ++e) {
            fmu_flat_name(&FMU_MODEL, data, g, e, name, sizeof name);
            printf("    <!-- %u -->\n    <ScalarVariable", ++vr);
            attr("name", name);
            printf(" valueReference=\"%u\" causality=\"%s\" variability=\"%s\"", vr, causality(2, v->causality),
                   variability(v->variability));
            if (v->causality == FMU_PARAMETER) printf(" initial=\"exact\"");
            if (v->causality == FMU_STRUCTURAL) printf(" initial=\"calculated\"");
            attr("description", v->description);
            printf(">\n      <%s", v->type == FMU_REAL ? "Real" : v->type == FMU_BOOLEAN ? "Boolean" : "Integer");
            if (v->causality == FMU_PARAMETER || v->causality == FMU_INPUT) {
                printf(" start=\"");
                value(data, g, e);
                putchar('"');
            }
            range(v);
            if (v->unit) printf(" unit=\"%s\"", v->unit);
            puts("/>\n    </ScalarVariable>");
        }
    }
    puts("  </ModelVariables>\n  <ModelStructure>\n    <Outputs>");
    vr = 0;
    for (int g = 0; g < FMU_MODEL.num_groups; ++g) {
        const size_t size = fmu_group_size(&FMU_MODEL, data, g);
        for (size_t e = 0; e < size; ++e, ++vr) {
            if (group(g)->causality != FMU_OUTPUT) continue;
            printf("      <Unknown index=\"%u\"", vr + 1);
            dependencies(data, 2, group(g));
            puts("/>");
        }
    }
    puts("    </Outputs>\n    <InitialUnknowns>");
    vr = 0;
    for (int g = 0; g < FMU_MODEL.num_groups; ++g) {
        const size_t size = fmu_group_size(&FMU_MODEL, data, g);
        for (size_t e = 0; e < size; ++e, ++vr) {
            if (group(g)->causality == FMU_OUTPUT || group(g)->causality == FMU_STRUCTURAL) {
                printf("      <Unknown index=\"%u\"/>\n", vr + 1);
            }
        }
    }
    puts("    </InitialUnknowns>\n  </ModelStructure>\n</fmiModelDescription>");
}

static const char *fmi3_type(fmu_type type)
{
    static const char *const names[] = {"Float64", "Int32", "Enumeration", "Boolean", "UInt64"};
    return names[type];
}

static void fmi3(void *data)
{
    char token[256];
    FMU_MODEL.token(data, 3, 0, token, sizeof token);
    header("3.0", "instantiationToken", token);
    puts(">");
    printf("  <CoSimulation modelIdentifier=\"%s\" canHandleVariableCommunicationStepSize=\"%s\""
           " canBeInstantiatedOnlyOncePerProcess=\"false\" providesIntermediateUpdate=\"false\""
           " hasEventMode=\"false\" canGetAndSetFMUState=\"true\" canSerializeFMUState=\"%s\"/>\n",
           FMU_MODEL.name, FMU_MODEL.variable_step ? "true" : "false", serializable());
    units();
    int any_enum = 0;
    for (int g = 0; g < FMU_MODEL.num_groups; ++g) any_enum |= group(g)->enumeration != NULL;
    if (any_enum) {
        puts("  <TypeDefinitions>");
        for (int g = 0; g < FMU_MODEL.num_groups; ++g) {
            const fmu_enum_type *t = group(g)->enumeration;
            int first = t != NULL;
            for (int h = 0; h < g && first; ++h) first = group(h)->enumeration != t;
            if (!first) continue;
            printf("    <EnumerationType name=\"%s\">\n", t->name);
            for (int i = 0; i < t->count; ++i) printf("      <Item name=\"%s\" value=\"%d\"/>\n", t->items[i], i);
            puts("    </EnumerationType>");
        }
        puts("  </TypeDefinitions>");
    }
    log_categories_and_experiment(data);
    puts("  <ModelVariables>");
    puts("    <Float64 name=\"time\" valueReference=\"0\" causality=\"independent\" variability=\"continuous\""
         " description=\"simulation time\"/>");
    for (int g = 0; g < FMU_MODEL.num_groups; ++g) {
        const fmu_variable_group *v = group(g);
        printf("    <%s", fmi3_type(v->type));
        attr("name", v->name);
        printf(" valueReference=\"%d\"", g + 1);
        if (v->enumeration) printf(" declaredType=\"%s\"", v->enumeration->name);
        printf(" causality=\"%s\" variability=\"%s\"", causality(3, v->causality), variability(v->variability));
        attr("description", v->description);
        if (v->causality != FMU_OUTPUT) {
            printf(" start=\"");
            const size_t size = fmu_group_size(&FMU_MODEL, data, g);
            for (size_t e = 0; e < size; ++e) {
                if (e) putchar(' ');
                value(data, g, e);
            }
            putchar('"');
        }
        if (v->enumeration == NULL) range(v);
        if (v->unit) printf(" unit=\"%s\"", v->unit);
        if (v->dims[0] == 0) {
            puts("/>");
            continue;
        }
        puts(">");
        for (int d = 0; d < FMU_MAX_DIMS && v->dims[d] != 0; ++d) {
            if (v->dims[d] < 0) printf("      <Dimension start=\"%d\"/>\n", -v->dims[d]);
            else printf("      <Dimension valueReference=\"%d\"/>\n", v->dims[d]);
        }
        printf("    </%s>\n", fmi3_type(v->type));
    }
    puts("  </ModelVariables>\n  <ModelStructure>");
    for (int g = 0; g < FMU_MODEL.num_groups; ++g) {
        if (group(g)->causality != FMU_OUTPUT) continue;
        printf("    <Output valueReference=\"%d\"", g + 1);
        dependencies(data, 3, group(g));
        puts("/>");
    }
    for (int g = 0; g < FMU_MODEL.num_groups; ++g) {
        if (group(g)->causality == FMU_OUTPUT) printf("    <InitialUnknown valueReference=\"%d\"/>\n", g + 1);
    }
    puts("  </ModelStructure>\n</fmiModelDescription>");
}

/* FMI 3 buildDescription.xml: the file names come as arguments (paths inside sources/). */
static void build_description(int argc, char **argv)
{
    puts("<?xml version=\"1.0\" encoding=\"UTF-8\"?>");
    puts("<fmiBuildDescription fmiVersion=\"3.0\">");
    printf("  <BuildConfiguration modelIdentifier=\"%s\" description=\"C11 sources and the Eigen backend in C++17"
           " (Eigen's headers in Eigen/, MPL2); link libm and the C++ runtime\">\n",
           FMU_MODEL.name);
    /* One set for both languages: fmpy 0.3.32 builds the first set only, with CMake, which compiles each
       file by its extension (a set's language attribute would set one standard for all). */
    puts("    <SourceFileSet>");
    for (int i = 0; i < argc; ++i) {
        if (compiled(argv[i])) printf("      <SourceFile name=\"%s\"/>\n", argv[i]);
    }
    puts("      <IncludeDirectory name=\".\"/>");
    puts("    </SourceFileSet>");
    puts("    <Library name=\"m\"/>");
    puts("  </BuildConfiguration>\n</fmiBuildDescription>");
}

static void json_string(const char *text)
{
    putchar('"');
    for (const char *p = text ? text : ""; *p; ++p) {
        if (*p == '"' || *p == '\\') putchar('\\');
        putchar(*p);
    }
    putchar('"');
}

static void json_number(double x)
{
    if (isfinite(x)) printf("%.17g", x);
    else printf("null");
}

/* The variable table as JSON, with the start values of the parameters (structural ones included). */
static void table(void *data)
{
    static const char *const types[] = {"real", "integer", "enumeration", "boolean", "size"};
    static const char *const causalities[] = {"structural", "parameter", "input", "output"};
    printf("{\n  \"model\": ");
    json_string(FMU_MODEL.name);
    printf(",\n  \"description\": ");
    json_string(FMU_MODEL.description);
    printf(",\n  \"generation_tool\": \"okid %s\",\n  \"variable_step\": %s,\n  \"can_serialize_state\": %s,\n"
           "  \"variables\": [\n", OKID_VERSION_STRING, FMU_MODEL.variable_step ? "true" : "false", serializable());
    for (int g = 0; g < FMU_MODEL.num_groups; ++g) {
        const fmu_variable_group *v = group(g);
        printf("    {\"name\": ");
        json_string(v->name);
        printf(", \"flat_name\": ");
        if (v->flat_name) json_string(v->flat_name);
        else printf("null");
        printf(", \"type\": \"%s\", \"causality\": \"%s\", \"variability\": \"%s\", \"dims\": [", types[v->type],
               causalities[v->causality], variability(v->variability));
        for (int d = 0; d < FMU_MAX_DIMS && v->dims[d] != 0; ++d) {
            if (d) printf(", ");
            if (v->dims[d] < 0) printf("%d", -v->dims[d]);
            else json_string(group(v->dims[d] - 1)->name);
        }
        printf("], \"start\": ");
        if (v->causality == FMU_OUTPUT || v->dims[0] != 0) {
            printf("null");
        } else {
            double x;
            int i;
            if (v->type == FMU_REAL) memcpy(&x, fmu_group_element(&FMU_MODEL, data, g, 0), sizeof x);
            else memcpy(&i, fmu_group_element(&FMU_MODEL, data, g, 0), sizeof i), x = i;
            json_number(x);
        }
        const int ranged = !(isnan(v->min) || isnan(v->max) || v->min > v->max || v->type == FMU_BOOLEAN);
        printf(", \"min\": ");
        json_number(ranged ? v->min : (double)NAN);
        printf(", \"max\": ");
        json_number(ranged ? v->max : (double)NAN);
        printf(", \"unit\": ");
        if (v->unit) json_string(v->unit);
        else printf("null");
        if (v->enumeration) {
            printf(", \"items\": [");
            for (int i = 0; i < v->enumeration->count; ++i) {
                if (i) printf(", ");
                json_string(v->enumeration->items[i]);
            }
            printf("]");
        }
        printf(", \"description\": ");
        json_string(v->description);
        printf(", \"depends_on\": ");
        if (v->depends_on) json_string(v->depends_on);
        else printf("null");
        printf("}%s\n", g + 1 < FMU_MODEL.num_groups ? "," : "");
    }
    printf("  ]\n}\n");
}

/* The model data with its start values, the configuration of `path` ("-": none) applied. */
static void *start_values(const char *path, unsigned long *hash)
{
    void *data = calloc(1, FMU_MODEL.data_bytes);
    static char config[8192];
    config[0] = '\0';
    *hash = 0;
    if (path && strcmp(path, "-") != 0) {
        FILE *f = fopen(path, "rb");
        const size_t n = f ? fread(config, 1, sizeof config - 1, f) : 0;
        if (f == NULL) {
            fprintf(stderr, "make_model_description: cannot read %s\n", path);
            exit(2);
        }
        fclose(f);
        config[n] = '\0';
        *hash = fmu_hash(config, n);
    }
    char error[300] = "the structural parameters are out of this build's range";
    FMU_MODEL.set_defaults(data);
    if (fmu_apply_config(&FMU_MODEL, data, config, error, sizeof error) != 0 ||
        (FMU_MODEL.configure && FMU_MODEL.configure(data, &MEMORY, NULL) != FMU_OK)) {
        fprintf(stderr, "make_model_description: configuration refused: %s\n", error);
        exit(2);
    }
    return data;
}

int main(int argc, char **argv)
{
    unsigned long hash = 0;
    if (argc >= 3 && strcmp(argv[1], "2") == 0) {
        void *data = start_values(argv[2], &hash); /* before hash is read */
        fmi2(data, hash, argc - 3, argv + 3);
    } else if (argc >= 2 && strcmp(argv[1], "3") == 0) {
        fmi3(start_values(NULL, &hash));
    } else if (argc >= 2 && strcmp(argv[1], "table") == 0) {
        table(start_values(NULL, &hash));
    } else if (argc >= 2 && strcmp(argv[1], "build") == 0) {
        build_description(argc - 2, argv + 2);
    } else {
        fprintf(stderr, "usage: %s 2 CONFIG|- [sources...] | 3 | table | build [sources...]\n", argv[0]);
        return 2;
    }
    return 0;
}
