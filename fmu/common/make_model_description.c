/*
 * Writes a model's modelDescription.xml (FMI 2.0 or 3.0) from the same variable table the FMU
 * runs on, so the description and the binary cannot disagree.
 *   make_model_description 2|3 > modelDescription.xml
 *   make_model_description build > buildDescription.xml   (FMI 3 sources/)
 */
#include <stdio.h>
#include <string.h>

#include "fmu_model.h"
#include "okid/okid.h"

/* The models log through this; describing them logs nothing. */
void fmu_log(fmu_logger *logger, fmu_status status, const char *category, const char *format, ...)
{
    (void)logger, (void)status, (void)category, (void)format;
}

static void attr_escaped(const char *name, const char *text)
{
    printf(" %s=\"", name);
    for (const char *p = text; *p; ++p) {
        switch (*p) {
        case '"': fputs("&quot;", stdout); break;
        case '&': fputs("&amp;", stdout); break;
        case '<': fputs("&lt;", stdout); break;
        case '>': fputs("&gt;", stdout); break;
        default: putchar(*p);
        }
    }
    putchar('"');
}

static int count(void) { return fmu_variable_count(FMU_MODEL.groups, FMU_MODEL.num_groups); }

static fmu_variable at(int i)
{
    fmu_variable v;
    fmu_variable_at(FMU_MODEL.groups, FMU_MODEL.num_groups, i, &v);
    return v;
}

static const char *causality(fmu_causality c)
{
    return c == FMU_PARAMETER ? "parameter" : c == FMU_INPUT ? "input" : "output";
}

static const char *variability(fmu_variability v)
{
    static const char *const names[] = {"fixed", "tunable", "discrete", "continuous"};
    return names[v];
}

static void units(void)
{
    const char *seen[32];
    int n = 0;
    for (int i = 0; i < count(); ++i) {
        const fmu_variable v = at(i);
        int known = v.unit == NULL;
        for (int j = 0; j < n && !known; ++j) known = strcmp(seen[j], v.unit) == 0;
        if (!known && n < 32) seen[n++] = v.unit;
    }
    if (n == 0) return;
    puts("  <UnitDefinitions>");
    for (int j = 0; j < n; ++j) printf("    <Unit name=\"%s\"/>\n", seen[j]);
    puts("  </UnitDefinitions>");
}

static void header_common(void)
{
    attr_escaped("modelName", FMU_MODEL.name);
    attr_escaped("description", FMU_MODEL.description);
    printf(" generationTool=\"okid %s\" variableNamingConvention=\"flat\"", OKID_VERSION_STRING);
}

static void log_categories(void)
{
    puts("  <LogCategories>");
    puts("    <Category name=\"logEvents\" description=\"identifications and other events\"/>");
    puts("    <Category name=\"logStatusWarning\" description=\"rejected samples and other warnings\"/>");
    puts("    <Category name=\"logStatusError\" description=\"refused calls and parameters, with the reason\"/>");
    puts("    <Category name=\"logAll\" description=\"everything\"/>");
    puts("  </LogCategories>");
    printf("  <DefaultExperiment startTime=\"0\" stopTime=\"10\" stepSize=\"%g\"/>\n", FMU_MODEL.default_step);
}

static void fmi2(void)
{
    puts("<?xml version=\"1.0\" encoding=\"UTF-8\"?>");
    printf("<fmiModelDescription fmiVersion=\"2.0\"");
    header_common();
    attr_escaped("guid", FMU_MODEL.token);
    puts(" numberOfEventIndicators=\"0\">");
    printf("  <CoSimulation modelIdentifier=\"%s\" canHandleVariableCommunicationStepSize=\"true\""
           " canBeInstantiatedOnlyOncePerProcess=\"false\" canNotUseMemoryManagementFunctions=\"true\"/>\n",
           FMU_MODEL.name);
    units();
    log_categories();
    puts("  <ModelVariables>");
    for (int i = 0; i < count(); ++i) {
        const fmu_variable v = at(i);
        printf("    <!-- %d -->\n    <ScalarVariable", i + 1);
        attr_escaped("name", v.name);
        printf(" valueReference=\"%d\" causality=\"%s\" variability=\"%s\"", i + 1, causality(v.causality),
               variability(v.variability));
        if (v.causality == FMU_PARAMETER) printf(" initial=\"exact\"");
        attr_escaped("description", v.description);
        printf(">\n      <%s", v.type == FMU_REAL ? "Real" : "Integer");
        if (v.causality != FMU_OUTPUT) {
            if (v.type == FMU_REAL) printf(" start=\"%.17g\"", v.start);
            else printf(" start=\"%d\"", (int)v.start);
        }
        if (v.unit) printf(" unit=\"%s\"", v.unit);
        puts("/>\n    </ScalarVariable>");
    }
    puts("  </ModelVariables>\n  <ModelStructure>\n    <Outputs>");
    for (int i = 0; i < count(); ++i) {
        if (at(i).causality == FMU_OUTPUT) printf("      <Unknown index=\"%d\"/>\n", i + 1);
    }
    puts("    </Outputs>\n    <InitialUnknowns>");
    for (int i = 0; i < count(); ++i) {
        if (at(i).causality == FMU_OUTPUT) printf("      <Unknown index=\"%d\"/>\n", i + 1);
    }
    puts("    </InitialUnknowns>\n  </ModelStructure>\n</fmiModelDescription>");
}

static void fmi3(void)
{
    puts("<?xml version=\"1.0\" encoding=\"UTF-8\"?>");
    printf("<fmiModelDescription fmiVersion=\"3.0\"");
    header_common();
    attr_escaped("instantiationToken", FMU_MODEL.token);
    puts(">");
    printf("  <CoSimulation modelIdentifier=\"%s\" canHandleVariableCommunicationStepSize=\"true\""
           " canBeInstantiatedOnlyOncePerProcess=\"false\" providesIntermediateUpdate=\"false\""
           " hasEventMode=\"false\"/>\n",
           FMU_MODEL.name);
    units();
    log_categories();
    puts("  <ModelVariables>");
    puts("    <Float64 name=\"time\" valueReference=\"0\" causality=\"independent\" variability=\"continuous\""
         " description=\"simulation time\"/>");
    for (int i = 0; i < count(); ++i) {
        const fmu_variable v = at(i);
        printf("    <%s", v.type == FMU_REAL ? "Float64" : "Int32");
        attr_escaped("name", v.name);
        printf(" valueReference=\"%d\" causality=\"%s\" variability=\"%s\"", i + 1, causality(v.causality),
               variability(v.variability));
        attr_escaped("description", v.description);
        if (v.causality != FMU_OUTPUT) {
            if (v.type == FMU_REAL) printf(" start=\"%.17g\"", v.start);
            else printf(" start=\"%d\"", (int)v.start);
        }
        if (v.unit) printf(" unit=\"%s\"", v.unit);
        puts("/>");
    }
    puts("  </ModelVariables>\n  <ModelStructure>");
    for (int i = 0; i < count(); ++i) {
        if (at(i).causality == FMU_OUTPUT) printf("    <Output valueReference=\"%d\"/>\n", i + 1);
    }
    for (int i = 0; i < count(); ++i) {
        if (at(i).causality == FMU_OUTPUT) printf("    <InitialUnknown valueReference=\"%d\"/>\n", i + 1);
    }
    puts("  </ModelStructure>\n</fmiModelDescription>");
}

/* FMI 3 buildDescription.xml: the file names come as arguments (paths inside sources/). */
static void build_description(int argc, char **argv)
{
    puts("<?xml version=\"1.0\" encoding=\"UTF-8\"?>");
    puts("<fmiBuildDescription fmiVersion=\"3.0\">");
    printf("  <BuildConfiguration modelIdentifier=\"%s\" description=\"C11; link LAPACKE, LAPACK, BLAS and libm\">\n",
           FMU_MODEL.name);
    puts("    <SourceFileSet language=\"C11\">");
    for (int i = 0; i < argc; ++i) {
        const size_t len = strlen(argv[i]);
        if (len > 2 && strcmp(argv[i] + len - 2, ".c") == 0) printf("      <SourceFile name=\"%s\"/>\n", argv[i]);
    }
    puts("      <IncludeDirectory name=\".\"/>");
    puts("    </SourceFileSet>");
    puts("    <Library name=\"lapacke\"/>\n    <Library name=\"lapack\"/>\n    <Library name=\"blas\"/>\n    <Library name=\"m\"/>");
    puts("  </BuildConfiguration>\n</fmiBuildDescription>");
}

int main(int argc, char **argv)
{
    if (argc >= 2 && strcmp(argv[1], "2") == 0) {
        fmi2();
    } else if (argc >= 2 && strcmp(argv[1], "3") == 0) {
        fmi3();
    } else if (argc >= 2 && strcmp(argv[1], "build") == 0) {
        build_description(argc - 2, argv + 2);
    } else {
        fprintf(stderr, "usage: %s 2|3|build [source files...]\n", argv[0]);
        return 2;
    }
    return 0;
}
