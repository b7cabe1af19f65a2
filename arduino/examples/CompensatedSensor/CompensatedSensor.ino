/* CompensatedSensor - readings corrected for temperature from a calibration
 * image kept in EEPROM, two slots (A/B) with CRC: a power cut while a new
 * calibration is written leaves the old one in use.
 *
 * The image is what pysig writes on the PC (`pysig fit ... --model`, then
 * `pysig export --format image`): any model family (polynomial, compact
 * polynomial, table), checked by its CRC-16 and sequence number.  On a
 * fresh chip (EEPROM erased) the factory image of factory_calibration.h
 * (kept in flash) is copied into slot A.  A new image sent on Serial as
 * 'I', two length bytes (little-endian), then the image, is checked and
 * written into the slot NOT in use; the loader then takes the newer one.
 *
 * readSensor() stands for your sensor: here the ATmega328P's own
 * temperature sensor (uncalibrated, datasheet typical values) and three
 * analog inputs. */
#include <avr/eeprom.h>
#include <avr/pgmspace.h>
#include <string.h>
#include <SigCore.h>
#include "factory_calibration.h"

static const uint16_t SLOT_BYTES = 128;       /* EEPROM per slot: A at 0, B at 128 */
static const uint16_t TABLE_ENTRIES = 96;     /* room for a table model: axes x knots */
static uint8_t slot_a[SLOT_BYTES], slot_b[SLOT_BYTES];
static int16_t table_storage[TABLE_ENTRIES];
static sig_tmodel model;
static uint8_t live_slot = 0xFF;

static void readSlots()
{
    eeprom_read_block(slot_a, (const void *)0, SLOT_BYTES);
    eeprom_read_block(slot_b, (const void *)SLOT_BYTES, SLOT_BYTES);
}

/* The newer valid slot -> model.  SIG_ERR_EMPTY when neither is valid. */
static sig_status loadCalibration()
{
    sig_status st = sig_image_select_slot(slot_a, SLOT_BYTES, slot_b, SLOT_BYTES, &live_slot);
    if (st < 0)
        return st;
    return sig_tmodel_load_image(&model, table_storage, TABLE_ENTRIES,
                                 live_slot == SIG_IMAGE_SLOT_A ? slot_a : slot_b, SLOT_BYTES);
}

static void installFactoryImage()
{
    memcpy_P(slot_a, factory_image, FACTORY_IMAGE_LEN);
    memset(slot_a + FACTORY_IMAGE_LEN, 0xFF, SLOT_BYTES - FACTORY_IMAGE_LEN);
    eeprom_update_block(slot_a, (void *)0, SLOT_BYTES);
}

/* A new image into the slot not in use, only if it is valid and newer. */
static sig_status storeImage(const uint8_t *image, uint16_t len)
{
    uint32_t seq_new, seq_live;
    const uint8_t *live = live_slot == SIG_IMAGE_SLOT_A ? slot_a : slot_b;
    sig_status st = sig_image_validate(image, len);
    if (st < 0 || len > SLOT_BYTES)
        return st < 0 ? st : SIG_ERR_ARG;
    if (sig_image_sequence(image, len, &seq_new) < 0 || sig_image_sequence(live, SLOT_BYTES, &seq_live) < 0
            || (int32_t)(seq_new - seq_live) <= 0)
        return SIG_ERR_ARG;
    eeprom_update_block(image, (void *)(live_slot == SIG_IMAGE_SLOT_A ? SLOT_BYTES : 0), len);
    readSlots();
    return loadCalibration();
}

/* Temperature in 0.01 degC and three raw readings: replace with your sensor. */
static void readSensor(int16_t *temp_centi, int16_t xyz[3])
{
    ADMUX = _BV(REFS1) | _BV(REFS0) | _BV(MUX3);   /* 1.1 V reference, channel 8 */
    delay(2);
    ADCSRA |= _BV(ADSC);
    while (ADCSRA & _BV(ADSC))
        ;
    *temp_centi = (int16_t)(((int32_t)ADCW - 324) * 100 * 100 / 122);   /* typical: 1.22 LSB/degC, 324 at 0 degC */
    xyz[0] = (int16_t)analogRead(A0);
    xyz[1] = (int16_t)analogRead(A1);
    xyz[2] = (int16_t)analogRead(A2);
}

static void receiveImage()
{
    static uint8_t buf[SLOT_BYTES];
    uint16_t len, i;
    if (Serial.readBytes(buf, 2) != 2)
        return;
    len = (uint16_t)(buf[0] | (uint16_t)buf[1] << 8);
    if (len > SLOT_BYTES || Serial.readBytes(buf, len) != len) {
        Serial.println(F("image: bad length"));
        return;
    }
    for (i = len; i < SLOT_BYTES; i++)
        buf[i] = 0xFF;
    Serial.print(F("image: status "));
    Serial.println(storeImage(buf, len));
}

void setup()
{
    sig_status st;
    Serial.begin(115200);
    readSlots();
    st = loadCalibration();
    if (st == SIG_ERR_EMPTY) {               /* fresh chip: the factory calibration */
        installFactoryImage();
        readSlots();
        st = loadCalibration();
    }
    Serial.print(F("calibration slot "));
    Serial.print(live_slot == SIG_IMAGE_SLOT_A ? 'A' : 'B');
    Serial.print(F(", status "));
    Serial.println(st);
}

void loop()
{
    int16_t t, raw[3], out[3];
    sig_status st;
    if (Serial.available() && Serial.read() == 'I')
        receiveImage();
    readSensor(&t, raw);
    st = sig_tmodel_apply(&model, (uint16_t)t, raw, out);   /* two's complement code of 0.01 degC */
    Serial.print(t);
    for (uint8_t a = 0; a < 3; a++) {
        Serial.print(' ');
        Serial.print(out[a]);
    }
    Serial.print(F(" status "));
    Serial.println(st);
    delay(500);
}
