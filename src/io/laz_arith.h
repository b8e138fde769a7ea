/* SPDX-License-Identifier: MIT
 * LAZ entropy decoding: the range (arithmetic) decoder over a byte stream, its
 * adaptive bit and symbol models (and lazily created families of them chosen by a
 * previous byte), and the integer corrector ("integer compressor") that LAZ items use
 * to decode a value as a prediction plus a coded correction.
 *
 * Design: the decoder reads a bounded byte range; bytes past its end read as zero and
 * are counted in `overrun`, so a truncated or corrupt stream never reads outside the
 * input and never loops: every decode call does a bounded amount of work. Callers
 * check `overrun` after each point and report the chunk as damaged.
 * Models adapt exactly as the LAZ format prescribes (counts, rescaling cadence and
 * the 13-bit / 15-bit probability precision), because the encoder made the same
 * updates; any difference would desynchronise the stream.
 *
 * Based on: M. Isenburg, "LASzip: lossless compression of LiDAR data",
 * Photogrammetric Engineering & Remote Sensing 79(2), 2013 (section "Arithmetic
 * coding", the corrector scheme); A. Said, "Introduction to arithmetic coding -
 * theory and practice", HP Labs report HPL-2004-76, 2004 (the range coder and the
 * adaptive models with periodic rescaling that LAZ adopts).
 */
#ifndef STA_IO_LAZ_ARITH_H
#define STA_IO_LAZ_ARITH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

enum {
    STA_LAZ_MIN_LENGTH = 0x01000000, /* renormalise below this interval length */
    STA_LAZ_BIT_SHIFT = 13,          /* bit model probability precision */
    STA_LAZ_BIT_MAX_COUNT = 1 << 13, /* bit model count before halving */
    STA_LAZ_SYM_SHIFT = 15,          /* symbol model distribution precision */
    STA_LAZ_SYM_MAX_COUNT = 1 << 15, /* symbol model count before halving */
    STA_LAZ_MAX_SYMBOLS = 1 << 11,   /* largest alphabet a model accepts */
};

/* The range decoder over bytes [p, end). */
typedef struct sta_laz_dec {
    const uint8_t *p;   /* next byte to read */
    const uint8_t *end; /* end of the readable bytes */
    uint32_t value;     /* code value minus the interval base */
    uint32_t length;    /* interval length, >= STA_LAZ_MIN_LENGTH between calls */
    uint32_t overrun;   /* bytes requested past `end` (read as zero) */
} sta_laz_dec;

/* Adaptive binary model. */
typedef struct sta_laz_bit_model {
    uint32_t bit_0_prob; /* P(0) in units of 2^-13 */
    uint32_t bit_0_count;
    uint32_t bit_count;
    uint32_t update_cycle;
    uint32_t bits_until_update;
} sta_laz_bit_model;

/* Adaptive model over `symbols` symbols (2..2048); heap object with its tables. */
typedef struct sta_laz_model {
    uint32_t symbols;
    uint32_t last_symbol;
    uint32_t table_size;  /* decoder lookup table entries, 0 when searching only */
    uint32_t table_shift; /* distribution value >> table_shift indexes the table */
    uint32_t total_count;
    uint32_t update_cycle;
    uint32_t symbols_until_update;
    uint32_t *distribution;  /* symbols entries, cumulative, 2^15 scale */
    uint32_t *symbol_count;  /* symbols entries */
    uint32_t *decoder_table; /* table_size + 2 entries, or NULL */
    uint32_t storage[];
} sta_laz_model;

/* Integer corrector: decodes prediction + correction in `bits` bits (1..32) with
 * `contexts` independent models for the correction's magnitude class. */
typedef struct sta_laz_ic {
    uint32_t bits;                /* corr_bits */
    uint32_t contexts;            /* number of magnitude models */
    uint32_t bits_high;           /* magnitudes above this many bits send low bits raw */
    uint32_t range;               /* 2^bits, 0 for 32 bits (wrap in uint32) */
    int32_t corr_min;             /* smallest correction */
    uint32_t k;                   /* magnitude class of the last correction */
    sta_laz_model **m_bits;       /* contexts models of bits + 1 symbols */
    sta_laz_bit_model corrector0; /* class 0: correction 0 or 1 */
    sta_laz_model *corrector[33]; /* class 1..bits */
    uint64_t stale_classes;       /* bit k: corrector[k] still awaits its reset */
    uint32_t stale_contexts;      /* bit c: m_bits[c] still awaits its reset */
} sta_laz_ic;

/* Starts decoding at `p` (reads the first four bytes). */
void sta_laz_dec_init(sta_laz_dec *dec, const uint8_t *p, const uint8_t *end);

void sta_laz_bit_model_init(sta_laz_bit_model *model);

/* A model of `symbols` symbols (2..2048), initialised; NULL when out of memory. */
sta_laz_model *sta_laz_model_create(uint32_t symbols);
/* Back to the initial (uniform) state. */
void sta_laz_model_reset(sta_laz_model *model);
void sta_laz_model_destroy(sta_laz_model *model);

/* The model for context `ctx` of a lazily allocated family of 256 models of 256
 * symbols (one per previous byte value), created on first use and reset once per
 * chunk: `used` (32 bytes) marks the models already reset in this chunk, the caller
 * clears it at chunk start. NULL when out of memory. */
sta_laz_model *sta_laz_context_model(sta_laz_model **models, uint8_t *used, uint8_t ctx);

/* The models' periodic adaptation (called by the decoder; exported for the test suite's
 * LAZ encoder, which must adapt exactly as the decoder does). */
void sta_laz_bit_model_update(sta_laz_bit_model *model);
void sta_laz_model_update(sta_laz_model *model);

uint32_t sta_laz_decode_bit(sta_laz_dec *dec, sta_laz_bit_model *model);
uint32_t sta_laz_decode_symbol(sta_laz_dec *dec, sta_laz_model *model);
/* `bits` (1..32) raw bits, least significant part first for more than 19. */
uint32_t sta_laz_read_bits(sta_laz_dec *dec, uint32_t bits);
uint32_t sta_laz_read_u32(sta_laz_dec *dec);

/* Allocates the corrector's models (1..32 bits, 1..32 contexts); false when out of
 * memory or out of range (then release it). */
bool sta_laz_ic_init(sta_laz_ic *ic, uint32_t bits, uint32_t contexts);
/* Resets every model to its initial state (start of a chunk). */
void sta_laz_ic_reset(sta_laz_ic *ic);
/* Frees the models; a zeroed struct is a no-op. */
void sta_laz_ic_release(sta_laz_ic *ic);
/* The models of magnitude class k (1..bits) and of context c, reset on first use
 * after sta_laz_ic_reset: a chunk start resets every model, and most of the classes
 * and contexts a chunk never touches (resetting them all cost more than decoding a
 * chunk of a thousand points). The encoder must take its models from here too. */
static inline sta_laz_model *sta_laz_ic_class_model(sta_laz_ic *ic, uint32_t k)
{
    if (ic->stale_classes & (1ull << k)) {
        ic->stale_classes &= ~(1ull << k);
        sta_laz_model_reset(ic->corrector[k]);
    }
    return ic->corrector[k];
}

static inline sta_laz_model *sta_laz_ic_context_model(sta_laz_ic *ic, uint32_t context)
{
    if (ic->stale_contexts & (1u << context)) {
        ic->stale_contexts &= ~(1u << context);
        sta_laz_model_reset(ic->m_bits[context]);
    }
    return ic->m_bits[context];
}

/* pred + decoded correction, wrapped into the corrector's range. */
int32_t sta_laz_ic_decode(sta_laz_ic *ic, sta_laz_dec *dec, int32_t pred, uint32_t context);

#endif
