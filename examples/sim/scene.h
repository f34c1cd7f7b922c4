/*
 * scene.h: the edmi text scene format, parsed into plain edmi data (host side only).
 *
 * A scene file declares bodies and exactly the effects that act on them, one per line
 * (format: docs/simulator.md). sim_scene_parse() turns it into the arrays an
 * edmi_scene points to, plus the force ports and the run settings the file may declare
 * (scheme, dt, t_end, tolerances). Nothing here is needed on a target: a firmware keeps the
 * same scene as static const data (see `edmi-sim SCENE --emit-c`).
 *
 * Hosted C99: stdio, stdlib and string.h are used. Every error is reported as
 * "FILE:LINE: message" naming the offending key, index or value.
 */
#ifndef EDMI_SIM_SCENE_H
#define EDMI_SIM_SCENE_H

#include <stddef.h>
#include "edmi.h"

/** Longest body name, including the terminating NUL. */
#define SIM_NAME_MAX 24
/** Longest scene line, including the newline. */
#define SIM_LINE_MAX 1024
/** Room for one error message. */
#define SIM_ERR_MAX 320

/** Off-diagonal masses a scene can hold: one per body and gap. */
#if EDMI_MAX_MASS_GAP > 0
#define SIM_MAX_MASS (EDMI_MAX_BODIES * EDMI_MAX_MASS_GAP)
#else
#define SIM_MAX_MASS 1
#endif

/* Walls a scene may declare (`wall`): edmi-sim's build capacity, at least one slot. */
#if EDMI_MAX_WALLS > 0
#define SIM_MAX_WALLS EDMI_MAX_WALLS
#else
#define SIM_MAX_WALLS 1
#endif

/** A parsed scene: bodies, links, dampers and field as edmi data, plus force ports and the
 *  settings the file declared. Large (it holds EDMI_MAX_* arrays): make it static. */
typedef struct sim_scene {
    int n_bodies;
    edmi_body body[EDMI_MAX_BODIES];
    char body_name[EDMI_MAX_BODIES][SIM_NAME_MAX]; /*!< "" for an unnamed body */
    int body_line[EDMI_MAX_BODIES];          /*!< line that declared each body (messages) */
    int n_links;
    edmi_link link[EDMI_MAX_LINKS];
    int link_line[EDMI_MAX_LINKS];           /*!< line that declared each link (messages) */
    int n_dampers;
    edmi_damper damper[EDMI_MAX_DAMPERS];
    int n_walls;                             /*!< walls: not scene data (sim_scene_add_walls) */
    edmi_wall wall[SIM_MAX_WALLS];
    int n_mass;                              /*!< off-diagonal masses (`mass A B m`) */
    edmi_mass_coupling mass[SIM_MAX_MASS];
    int has_field;
    edmi_real g[3];                          /*!< field acceleration [L/T^2] */
    int n_forces;                            /*!< force ports */
    int force_body[EDMI_MAX_BODIES];         /*!< body of port i */
    edmi_real force[EDMI_MAX_BODIES][3];     /*!< force of port i [M L/T^2] */
    edmi_params params;                      /*!< edmi_default_params() edited by `set` */
    double dt;                               /*!< `set dt`, or 0 when the file has none */
    double t_end;                            /*!< `set t_end`, or 0 when the file has none */
    long every;                              /*!< `set every`, or 0 when the file has none */
    char title[128];                         /*!< `title` text, or "" */
} sim_scene;

/** \brief Parse scene text.
 *  \param[in] text NUL-terminated scene text
 *  \param[in] file name used in messages
 *  \param[out] out the scene (zeroed first)
 *  \param[out] err on failure "FILE:LINE: message" (or "FILE: message" for the whole file)
 *  \return 0 on success, -1 on the first error */
int sim_scene_parse(const char *text, const char *file, sim_scene *out, char *err,
                    size_t err_size);

/** \brief Read and parse a scene file. \return 0 on success, -1 with err set. */
int sim_scene_load(const char *path, sim_scene *out, char *err, size_t err_size);

/** \brief The edmi_scene view of a parsed scene (pointers into *s; params point to s->params). */
edmi_scene sim_scene_view(const sim_scene *s);

/** \brief Add the scene's walls to a system edmi_load_scene() loaded from its view
 *  (edmi_add_wall(); an edmi_scene holds no walls). \return EDMI_OK or edmi_add_wall's status. */
edmi_status sim_scene_add_walls(const sim_scene *s, edmi_system *sys);

/** \brief Parse a scheme name: mp, lg, ge, pm, pt. \return 0 on success, -1 if unknown. */
int sim_parse_scheme(const char *word, edmi_scheme *out);

/** \brief Parse an LG switch name: closed (EDMI_LG_CLOSED) or janz, gonzalez, ge, pm, pt
 *  (EDMI_LG_QUOTIENT with that alternate). \return 0 on success, -1 if unknown. */
int sim_parse_lg_switch(const char *word, edmi_params *prm);

/** \brief Parse a guard mode: auto, on, off. \return 0 on success, -1 if unknown. */
int sim_parse_guard(const char *word, edmi_guard_mode *out);

/** \brief Parse on (1) or off (0). \return 0 on success, -1 otherwise. */
int sim_parse_on_off(const char *word, int *out);

/** \brief "auto", "on" or "off" for a guard mode. */
const char *sim_guard_word(edmi_guard_mode g);

/** \brief "mp", "lg", ... for a scheme; "closed", "janz", ... for an LG form/alternate. */
const char *sim_scheme_word(edmi_scheme s);
const char *sim_lg_switch_word(const edmi_params *prm);

#endif /* EDMI_SIM_SCENE_H */
