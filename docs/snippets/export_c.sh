# Fit Rigid to the embedded campaign A (a synthetic surrogate) and save it; export it as a C header.
bouncelab fit Rigid A --method structured --save rigid_A.json > /dev/null
bouncelab export rigid_A.json --lang c -o rigid_A.h
# The header's top comment: the law, conventions, units, parameters, validity domain, how to compile.
sed -n '1,/^ \*\//p' rigid_A.h
cat > main.c <<'C'
#include <stdio.h>
#include "rigid_A.h"

int main(void) {
    /* two landings [xdot, ydot, omega] in radii/s and rad/s, row-major */
    double landing[2][3] = {{1000.0, -800.0, 300.0}, {600.0, -900.0, 1500.0}};
    double liftoff[2][3];
    bouncelab_predict(&landing[0][0], &liftoff[0][0], 2);
    for (int i = 0; i < 2; i++)
        printf("%.6g %.6g %.6g -> %.6g %.6g %.6g\n", landing[i][0], landing[i][1], landing[i][2],
               liftoff[i][0], liftoff[i][1], liftoff[i][2]);
    double out[3];
    int code = bouncelab_predict_one(600.0, -900.0, 1500.0, out);  /* one bounce, and its regime */
    printf("regime of the second: %d (%s)\n", code, bouncelab_regime_name(code));
    return 0;
}
C
cc -std=c99 -O2 -ffp-contract=off main.c -lm -o bounce && ./bounce
# bouncelab's own numbers for the same landings:
bouncelab predict rigid_A.json --landing 1000 -800 300 --landing 600 -900 1500 2> /dev/null
