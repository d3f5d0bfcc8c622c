/* The PETSc/SLEPc API squeal binds to (bindgen input). */
#include <petscsys.h>
#include <petscvec.h>
#include <petscmat.h>
#include <petscksp.h>
#include <petscsnes.h>
#include <petscviewer.h>
#include <slepcsys.h>
#include <slepceps.h>
#include <slepcpep.h>
