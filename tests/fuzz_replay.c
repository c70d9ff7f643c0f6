/* SPDX-License-Identifier: Apache-2.0 */
/* Replays fuzz inputs (the seed corpus and every past finding) through a fuzz target's entry point
   in the ordinary build, so they run as regression tests under ctest, ASan and valgrind:
     fuzz_replay_api FILE...   */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int main(int argc, char **argv)
{
    for (int i = 1; i < argc; ++i) {
        FILE *f = fopen(argv[i], "rb");
        if (f == NULL) {
            fprintf(stderr, "cannot open %s\n", argv[i]);
            return 1;
        }
        static uint8_t data[1 << 20];
        const size_t size = fread(data, 1, sizeof data, f);
        fclose(f);
        LLVMFuzzerTestOneInput(data, size);
    }
    printf("replayed %d inputs\n", argc - 1);
    return 0;
}
