#pragma once
// The Abaqus umat interface of src/umat/dualcell_umat.c (Fortran calling convention: every
// argument by reference, the length of cmname last), for the tests that call it directly.
#include <cstddef>

extern "C" void umat_(double* stress, double* statev, double* ddsdde, double* sse, double* spd, double* scd,
                      double* rpl, double* ddsddt, double* drplde, double* drpldt, const double* stran,
                      const double* dstran, const double* time, const double* dtime, const double* temp,
                      const double* dtemp, const double* predef, const double* dpred, const char* cmname,
                      const int* ndi, const int* nshr, const int* ntens, const int* nstatv, const double* props,
                      const int* nprops, const double* coords, const double* drot, double* pnewdt, const double* celent,
                      const double* dfgrd0, const double* dfgrd1, const int* noel, const int* npt, const int* layer,
                      const int* kspt, const int* kstep, const int* kinc, std::size_t cmname_length);
