/* HX711Scale - a kitchen/shop scale on an HX711: the default weighing chain
 * (noise measured on the fly, impulse limit, anti-pulse window, Kalman,
 * stable flag, zero tracking), tare at boot and on command.
 *
 * Wiring: HX711 DOUT -> pin 3, SCK -> pin 2, rate pin high (80 SPS) or low
 * (10 SPS).  Serial 115200: one line per sample "kg stable"; send 't' to
 * tare.  Set COUNTS_PER_KG from a known weight (pysig calibrate-scale does
 * it from a recording).
 *
 * The HX711 read is this sketch's (bit-banged: 24 bits MSB first, a 25th
 * pulse selects channel A, gain 128 for the next conversion); the
 * filtering is the library's. */
#include <SigCore.h>

static const uint8_t DOUT_PIN = 3;
static const uint8_t SCK_PIN = 2;
static const float COUNTS_PER_KG = 2183.0f;   /* your cell: raw counts per kg */

static sig_chain_q chain;
static bool tare_done = false;

static bool hx711Ready()
{
    return digitalRead(DOUT_PIN) == LOW;
}

/* One conversion as a signed 24-bit code. */
static int32_t hx711Read()
{
    uint32_t raw = 0;
    noInterrupts();              /* SCK high for > 60 us powers the HX711 down */
    for (uint8_t i = 0; i < 24; i++) {
        digitalWrite(SCK_PIN, HIGH);
        raw = (raw << 1) | (uint32_t)digitalRead(DOUT_PIN);
        digitalWrite(SCK_PIN, LOW);
    }
    digitalWrite(SCK_PIN, HIGH); /* 25th pulse: channel A, gain 128 */
    digitalWrite(SCK_PIN, LOW);
    interrupts();
    if (raw & 0x800000UL)        /* sign-extend the two's complement code */
        raw |= 0xFF000000UL;
    return (int32_t)raw;
}

void setup()
{
    sig_chain_params_q params;
    Serial.begin(115200);
    pinMode(SCK_PIN, OUTPUT);
    pinMode(DOUT_PIN, INPUT);
    digitalWrite(SCK_PIN, LOW);
    sig_chain_defaults_q(&params);
    if (sig_chain_init_q(&chain, &params) != SIG_OK)
        Serial.println(F("chain parameters rejected"));
    sig_chain_tare_q(&chain);    /* takes effect at the first stable sample */
}

void loop()
{
    int32_t out_q7;              /* counts x 128, tare removed */
    bool stable;
    sig_status st;
    if (Serial.available() && Serial.read() == 't')
        sig_chain_tare_q(&chain);
    if (!hx711Ready())
        return;
    st = sig_chain_step_q(&chain, hx711Read(), &out_q7, &stable);
    if (st < 0)
        return;                  /* cannot happen with valid parameters; the state is unchanged */
    if (st & SIG_CHAIN_TARED)
        tare_done = true;
    Serial.print((float)out_q7 / (128.0f * COUNTS_PER_KG), 3);
    Serial.print(stable ? F(" stable") : F(" moving"));
    Serial.println(tare_done ? F("") : F(" (tare pending)"));
}
