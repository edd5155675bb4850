/* vsv_cf_names.c — what the CF export says a species is: its CF standard
 * name, and its unit as UDUNITS spells it.
 *
 * Source of the names: the CF Standard Name Table
 * (https://cfconventions.org/standard-names.html); every name below was
 * checked present in a 2018 copy of the table. A name is given only where
 * the species is that quantity and its unit converts to the name's
 * canonical unit (mole and mass fractions and mixing ratios: 1); a gas
 * given as a mass concentration (ug m-3) gets none, nor do fields such as
 * WRF's T (a perturbation potential temperature) that share a name with
 * one in another model.
 *
 * Mixing ratios: MM5 and WRF write every hydrometeor as a mixing ratio (kg
 * per kg of dry air). CF names that for cloud water, cloud ice and water
 * vapour; for rain, snow and graupel it has only the mass fraction (per kg
 * of moist air), which the mixing ratio exceeds by the air's water content
 * (a few per cent at most): those entries say so in the variable's
 * comment. */
#include "vsv_format.h"

#include <string.h>

typedef struct entry {
    const char *model; /* prefix of the file's model ("" any) */
    const char *names; /* the species' names, space-separated */
    const char *standard_name;
    int kind; /* what the unit must convert to */
    const char *comment;
} entry;

enum { DIMLESS, KELVIN, SPEED, PERCENT };

static const char approx[] =
    "the model's mixing ratio (per kg of dry air); CF has only the mass fraction (per kg of moist air), "
    "which is smaller by the air's water content (a few per cent at most)";

static const entry table[] = {
    {"MM5", "CLW", "cloud_liquid_water_mixing_ratio", DIMLESS, NULL},
    {"WRF", "QCLOUD", "cloud_liquid_water_mixing_ratio", DIMLESS, NULL},
    {"MM5", "ICE", "cloud_ice_mixing_ratio", DIMLESS, NULL},
    {"WRF", "QICE", "cloud_ice_mixing_ratio", DIMLESS, NULL},
    {"MM5", "Q", "humidity_mixing_ratio", DIMLESS, NULL},
    {"WRF", "QVAPOR", "humidity_mixing_ratio", DIMLESS, NULL},
    {"MM5", "RNW", "mass_fraction_of_rain_in_air", DIMLESS, approx},
    {"WRF", "QRAIN", "mass_fraction_of_rain_in_air", DIMLESS, approx},
    {"MM5", "SNOW", "mass_fraction_of_snow_in_air", DIMLESS, approx},
    {"WRF", "QSNOW", "mass_fraction_of_snow_in_air", DIMLESS, approx},
    {"MM5", "GRAUPEL", "mass_fraction_of_graupel_in_air", DIMLESS, approx},
    {"WRF", "QGRAUP", "mass_fraction_of_graupel_in_air", DIMLESS, approx},
    {"MM5", "T", "air_temperature", KELVIN, NULL},
    {"MM5", "U", "x_wind", SPEED, NULL},
    {"MM5", "V", "y_wind", SPEED, NULL},
    {"MM5", "W", "upward_air_velocity", SPEED, NULL},
    {"WRF", "W", "upward_air_velocity", SPEED, NULL},
    /* gases of the air-quality models, as mole fractions (ppm, ppb) */
    {"", "O3", "mole_fraction_of_ozone_in_air", DIMLESS, NULL},
    {"", "NO", "mole_fraction_of_nitrogen_monoxide_in_air", DIMLESS, NULL},
    {"", "NO2", "mole_fraction_of_nitrogen_dioxide_in_air", DIMLESS, NULL},
    {"", "N2O5", "mole_fraction_of_dinitrogen_pentoxide_in_air", DIMLESS, NULL},
    {"", "CO", "mole_fraction_of_carbon_monoxide_in_air", DIMLESS, NULL},
    {"", "SO2", "mole_fraction_of_sulfur_dioxide_in_air", DIMLESS, NULL},
    {"", "FORM HCHO", "mole_fraction_of_formaldehyde_in_air", DIMLESS, NULL},
    {"", "NH3", "mole_fraction_of_ammonia_in_air", DIMLESS, NULL},
    {"", "HNO3", "mole_fraction_of_nitric_acid_in_air", DIMLESS, NULL},
    {"", "HONO", "mole_fraction_of_nitrous_acid_in_air", DIMLESS, NULL},
    {"", "H2O2", "mole_fraction_of_hydrogen_peroxide_in_air", DIMLESS, NULL},
    {"", "ISOP ISOPRENE", "mole_fraction_of_isoprene_in_air", DIMLESS, NULL},
    {"", "PAN", "mole_fraction_of_peroxyacetyl_nitrate_in_air", DIMLESS, NULL},
    {"", "ETHA ETHANE", "mole_fraction_of_ethane_in_air", DIMLESS, NULL},
    {"", "TOL", "mole_fraction_of_toluene_in_air", DIMLESS, NULL},
    {"", "CH4", "mole_fraction_of_methane_in_air", DIMLESS, NULL},
    {"CAMx", "HUMIDITY", "mole_fraction_of_water_vapor_in_air", DIMLESS, NULL},
    /* the built-ins of vsv-convert --derive (an expression may not take
     * their names); total condensate has no CF name */
    {"", "theta", "air_potential_temperature", KELVIN, NULL},
    {"", "wind_speed", "wind_speed", SPEED, NULL},
    {"", "rh", "relative_humidity", PERCENT, NULL},
    /* the stored wind (vsv_vector.h: earth-relative components) */
    {"", VSV_WIND_EAST, "eastward_wind", SPEED, NULL},
    {"", VSV_WIND_NORTH, "northward_wind", SPEED, NULL},
    {"", VSV_WIND_UP, "upward_air_velocity", SPEED, NULL},
};

/* Model spellings UDUNITS does not know, and the unit they mean. */
static const struct {
    const char *model, *udunits;
} spellings[] = {
    {"ppmV", "ppm"},       {"ppmv", "ppm"},
    {"PPMV", "ppm"},       {"ppbV", "ppb"},
    {"ppbv", "ppb"},       {"PPBV", "ppb"},
    {"pptV", "ppt"},       {"micrograms/m**3", "ug m-3"},
    {"ug/m**3", "ug m-3"}, {"molecules/cm**3", "cm-3"},
};

const char *vsv_cf_units(const char *units)
{
    for (size_t i = 0; i < sizeof spellings / sizeof *spellings; i++)
        if (!strcmp(units, spellings[i].model))
            return spellings[i].udunits;
    return units;
}

/* 1 when the UDUNITS unit u is of the kind (only the spellings the
 * readers write: a unit we do not know gets no standard name). */
static int unit_of(const char *u, int kind)
{
    static const char *const dimless[] = {"1",   "kg/kg",   "kg kg-1",   "g/kg", "g kg-1", "ppm", "ppb",
                                          "ppt", "mol/mol", "mol mol-1", "ppmv", "ppbv",   "pptv"};
    static const char *const kelvin[] = {"K"};
    static const char *const speed[] = {"m/s", "m s-1"};
    static const char *const percent[] = {"%", "1"};
    const char *const *set = kind == DIMLESS ? dimless : kind == KELVIN ? kelvin : kind == SPEED ? speed : percent;
    const size_t n = kind == DIMLESS ? sizeof dimless / sizeof *dimless : kind == KELVIN ? 1 : 2;
    for (size_t i = 0; i < n; i++)
        if (!strcmp(u, set[i]))
            return 1;
    return 0;
}

/* 1 when name is one of the space-separated words of list. */
static int one_of(const char *name, const char *list)
{
    const size_t n = strlen(name);
    for (const char *p = list; *p;) {
        const size_t w = strcspn(p, " ");
        if (w == n && !strncmp(p, name, n))
            return 1;
        p += w + (p[w] == ' ');
    }
    return 0;
}

const char *vsv_cf_standard_name(const char *model, const char *name, const char *units, const char **comment)
{
    const char *u = vsv_cf_units(units);
    *comment = NULL;
    for (size_t i = 0; i < sizeof table / sizeof *table; i++) {
        const entry *e = &table[i];
        if (strncmp(model, e->model, strlen(e->model)) || !one_of(name, e->names) || !unit_of(u, e->kind))
            continue;
        *comment = e->comment;
        return e->standard_name;
    }
    return NULL;
}
