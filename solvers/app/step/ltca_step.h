#ifndef LTCA_STEP_H
#define LTCA_STEP_H
/* The STEP writer's entry point (docs/export.md): the shared module ltca_step.so, which alone links
 * OpenCASCADE, and which `ltca geometry --step` loads with dlopen() from the executable's folder, so
 * that no other command loads OpenCASCADE. Plain C types only: nothing of OpenCASCADE or of ltca's
 * C++ crosses this line. mm throughout, the disc's body frame, the disc centre at the origin. */
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#define LTCA_STEP_ABI_VERSION 1
#define LTCA_STEP_ENTRY "ltca_step_write"

/* The disc: a closed outline in smooth pieces, circular holes through it, a width. */
typedef struct LtcaStepDisc {
  int abi_version;             /* LTCA_STEP_ABI_VERSION */
  int piece_count;             /* smooth pieces of the outline, counter-clockwise */
  const int* piece_offsets;    /* piece_count + 1 offsets into points_xy (in points); a piece's last
                                  point is the next piece's first (the last piece's, the first's) */
  const double* points_xy;     /* x0, y0, x1, y1, ...: points on the analytic curve the B-spline
                                  of each piece interpolates */
  const int* check_offsets;    /* piece_count + 1 offsets into check_xy */
  const double* check_xy;      /* more points on the analytic curve, between the interpolated
                                  ones: each piece's B-spline is measured against them */
  int hole_count;
  const double* holes_xyr;     /* centre x, centre y, radius of each hole (the bore, pin holes) */
  double width_mm;             /* the face width: the outline is extruded from z = 0 to z = width */
  double tolerance_mm;         /* the largest deviation of a check point allowed (else no file) */
  const char* path;            /* the file to write */
  const char* description;     /* the STEP header's FILE_DESCRIPTION (the model that ran) */
  const char* name;            /* the STEP header's FILE_NAME name (the file as the user named it) */
} LtcaStepDisc;

typedef struct LtcaStepReport {
  double max_node_deviation_mm;   /* of the interpolated points from their B-spline */
  double max_check_deviation_mm;  /* of the check points from their B-spline */
  int poles;                      /* B-spline poles, all pieces */
  int solid_valid;                /* BRepCheck_Analyzer on the solid before writing */
  char error[512];                /* why not, when the call returns non-zero */
} LtcaStepReport;

/* Writes the disc as one solid to disc->path. 0: written; non-zero: nothing usable was written,
 * report->error says why. Never throws. */
typedef int (*LtcaStepWriteFn)(const LtcaStepDisc* disc, LtcaStepReport* report);
int ltca_step_write(const LtcaStepDisc* disc, LtcaStepReport* report);

#ifdef __cplusplus
}
#endif
#endif
