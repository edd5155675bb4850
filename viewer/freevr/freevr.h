/* freevr.h — declarations only, written by the Vesuvius project from the
 * facts in ../shared/docs/FREEVR.md (FreeVR 0.6f / 0.7 API): `make test`
 * compiles the FreeVR back end with -fsyntax-only against them, and they are
 * the header of the project's FreeVR stand-in (tests/freevr-standin/), which
 * `make test` builds the back end against. It is not FreeVR's header: builds
 * for a real FreeVR use $FREEVR_DIR/include/freevr.h. */
#ifndef VSV_FREEVR_DECLS_H
#define VSV_FREEVR_DECLS_H
#pragma GCC system_header /* FreeVR's own C style (unprototyped callbacks) */

#include <stddef.h>

typedef struct vrContextInfo vrContextInfo;
typedef struct vrRenderInfo vrRenderInfo;
typedef struct vrCallback vrCallback;
typedef void *vrLock;

typedef struct {
    double v[16]; /* OpenGL column order */
} vrMatrix;
typedef struct {
    double v[3];
} vrPoint;
typedef struct {
    double v[3];
} vrVector;

typedef enum {
    VRFUNC_DISPLAY_INIT,
    VRFUNC_DISPLAY_FRAME,
    VRFUNC_DISPLAY,
    VRFUNC_DISPLAY_EYE = VRFUNC_DISPLAY,
    VRFUNC_DISPLAY_SIM,
    VRFUNC_DISPLAY_EXIT
} vrFuncType;

typedef enum { VRDIR_FORE, VRDIR_BACK, VRDIR_LEFT, VRDIR_RIGHT, VRDIR_UP, VRDIR_DOWN } vrDirection;

#define VR_ALLUSERS (-1)
enum { VR_X, VR_Y, VR_Z };

long vrShmemInit(size_t bytes);
void *vrShmemAlloc0(size_t bytes);
vrContextInfo *vrConfigure(int *argc, char **argv, char **appargs);
void vrCallbackSet(vrFuncType type, char *name, void (*fn)(), int argc, ...);
void vrFunctionSetCallback(vrFuncType type, vrCallback *cb);
vrCallback *vrCallbackCreate(void (*fn)(), int argc, ...);
void vrStart(void);
int vrFrame();
void vrExit();
double vrCurrentSimTime();

int vrGet2switchValue(int n);
int vrGet2switchDelta(int n);
float vrGetValuatorValue(int n);
float vrGetValuatorDelta(int n);
vrMatrix *vrMatrixGet6sensorValues(vrMatrix *m, int n);
vrPoint *vrPointGetRWFrom6sensor(vrPoint *p, int n);
vrVector *vrVectorGetRWFrom6sensorDir(vrVector *v, int n, vrDirection d);
int vrInputSet2switchDescription(int n, char *text);

void vrRenderTransformUserTravel(vrRenderInfo *ri);
void vrUserTravelLockSet(int user);
void vrUserTravelTranslate3d(int user, double x, double y, double z);
void vrUserTravelRotateId(int user, int axis, double degrees);
void vrUserTravelReset(int user);
void vrUserTravelLockRelease(int user);

vrLock vrNCLockCreate(void);
#define vrLockCreate() vrNCLockCreate()
void vrLockWriteSet(vrLock l);
void vrLockWriteRelease(vrLock l);
void vrLockReadSet(vrLock l);
void vrLockReadRelease(vrLock l);

#endif
