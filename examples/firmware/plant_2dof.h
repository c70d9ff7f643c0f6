/*
 * The plant the firmware example identifies: the paper's 2-DOF structure (m1 = 2, m2 = 3 kg,
 * r = 2, 4, 3 N s/m, k = 20, 40, 30 N/m, force on mass 1, accelerations of both masses),
 * discretised with a zero-order hold. On a real controller the sensors replace it.
 */
#ifndef OKID_PLANT_2DOF_H
#define OKID_PLANT_2DOF_H

#include "okid/okid.h"

enum { PLANT_DOFS = 2, PLANT_STATES = 4, PLANT_INPUTS = 1, PLANT_OUTPUTS = 2 };

typedef struct plant_2dof {
    okid_real a[PLANT_STATES * PLANT_STATES], b[PLANT_STATES * PLANT_INPUTS];
    okid_real c[PLANT_OUTPUTS * PLANT_STATES], d[PLANT_OUTPUTS * PLANT_INPUTS];
} plant_2dof;

/* Discrete model {A, B, C, D} of the structure for the sample interval dt (eq. 65-82, 13-14). */
okid_status plant_2dof_build(plant_2dof *plant, okid_real dt);

#endif
