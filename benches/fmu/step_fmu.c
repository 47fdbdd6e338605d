/* A minimal FMI 3.0 co-simulation importer in C, to time an FMU's stepping without
 * Python (docs/design.md, "The FMU"): it loads the FMU's library from an unzipped FMU,
 * instantiates it, steps it N times at a communication step H and reads the outputs
 * after each step, and prints the CPU time of the stepping loop and the last outputs.
 *
 *   cc -O2 -o step_fmu benches/fmu/step_fmu.c -ldl
 *   ./step_fmu UNZIPPED_DIR MODEL_IDENTIFIER TOKEN H N FIRST_OUTPUT_VR N_OUTPUTS
 */
#include <dlfcn.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

typedef void *Instance;
typedef int Status;
typedef void (*Log)(void *, Status, const char *, const char *);

static void log_message(void *env, Status status, const char *category, const char *message) {
    (void)env;
    fprintf(stderr, "[%d %s] %s\n", status, category, message);
}

static double cpu_seconds(void) {
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

typedef Instance (*Instantiate)(const char *, const char *, const char *, bool, bool, bool, bool,
                                const uint32_t *, size_t, void *, Log, void *);
typedef Status (*EnterInitialization)(Instance, bool, double, double, bool, double);
typedef Status (*Call)(Instance);
typedef Status (*DoStep)(Instance, double, double, bool, bool *, bool *, bool *, double *);
typedef Status (*GetFloat64)(Instance, const uint32_t *, size_t, double *, size_t);
typedef void (*Free)(Instance);

#define LOAD(type, name) type name = (type)dlsym(lib, #name); if (!name) { fprintf(stderr, "no %s\n", #name); return 2; }

int main(int argc, char **argv) {
    if (argc != 8) {
        fprintf(stderr, "usage: %s UNZIPPED_DIR MODEL_IDENTIFIER TOKEN H N FIRST_OUTPUT_VR N_OUTPUTS\n", argv[0]);
        return 2;
    }
    char path[4096], resources[4096];
    snprintf(path, sizeof path, "%s/binaries/x86_64-linux/%s.so", argv[1], argv[2]);
    snprintf(resources, sizeof resources, "%s/resources/", argv[1]);
    double h = atof(argv[4]);
    long n = atol(argv[5]);
    uint32_t first = (uint32_t)atol(argv[6]);
    size_t n_out = (size_t)atol(argv[7]);
    void *lib = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!lib) { fprintf(stderr, "%s\n", dlerror()); return 2; }
    LOAD(Instantiate, fmi3InstantiateCoSimulation)
    LOAD(EnterInitialization, fmi3EnterInitializationMode)
    LOAD(Call, fmi3ExitInitializationMode)
    LOAD(DoStep, fmi3DoStep)
    LOAD(GetFloat64, fmi3GetFloat64)
    LOAD(Call, fmi3Terminate)
    LOAD(Free, fmi3FreeInstance)
    Instance fmu = fmi3InstantiateCoSimulation("c", argv[3], resources, false, false, false, false,
                                               NULL, 0, NULL, log_message, NULL);
    if (!fmu) return 1;
    if (fmi3EnterInitializationMode(fmu, false, 0, 0, false, 0) || fmi3ExitInitializationMode(fmu)) return 1;
    uint32_t *vrs = malloc(n_out * sizeof *vrs);
    double *values = malloc(n_out * sizeof *values);
    for (size_t k = 0; k < n_out; k++) vrs[k] = first + (uint32_t)k;
    bool event, terminate, early;
    double last;
    double c0 = cpu_seconds();
    for (long k = 0; k < n; k++) {
        if (fmi3DoStep(fmu, k * h, h, true, &event, &terminate, &early, &last)) return 1;
        if (fmi3GetFloat64(fmu, vrs, n_out, values, n_out)) return 1;
    }
    double cpu = cpu_seconds() - c0;
    printf("%ld steps of %g s: %.3f s CPU; t = %.17g, first output %.17g\n", n, h, cpu, last, values[0]);
    fmi3Terminate(fmu);
    fmi3FreeInstance(fmu);
    free(vrs);
    free(values);
    return 0;
}
